"""The Klipper checkout the Klipper goldens run (gen_smoothing.py, compare_klipper_pick.py):
Klipper3d/klipper at commit 84104bb, its files checked by sha256 before any is imported."""
import hashlib
import os
import sys

SHA256 = {
    "scripts/calibrate_shaper.py": "2b78173855a55a8968dfef8421551b630ad478df89df21e8444f42d5e0d49d44",
    "klippy/extras/shaper_calibrate.py": "695d35f2d1f261109cbed3a8185a900bcce75f7cef1740920fec8a338701138c",
    "klippy/extras/shaper_defs.py": "1d8627c8864f6ff683a160fece2197e00b1d4acb12bdd1d743a6a73b6b3f05fe",
}


def verify(root, files):
    """Exits naming the file when one of `files` (paths in SHA256) differs from the pinned commit's."""
    for rel in files:
        with open(os.path.join(root, rel), "rb") as f:
            got = hashlib.sha256(f.read()).hexdigest()
        if got != SHA256[rel]:
            sys.exit(f"{rel}: sha256 {got}, expected {SHA256[rel]} (another Klipper commit)")
