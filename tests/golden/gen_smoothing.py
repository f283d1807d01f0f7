#!/usr/bin/python3
"""Golden smoothing and max_accel figures from Klipper's own code, for advise::smoothing_mm and
advise::max_accel_mm_s2 (tests/advise/test_smoothing.cpp).

Reference: Klipper (github.com/Klipper3d/klipper), commit 84104bbbd7625d28b4eaaad83f4562972460ecd9,
  klippy/extras/shaper_calibrate.py  sha256 695d35f2d1f261109cbed3a8185a900bcce75f7cef1740920fec8a338701138c
  klippy/extras/shaper_defs.py       sha256 1d8627c8864f6ff683a160fece2197e00b1d4acb12bdd1d743a6a73b6b3f05fe
Klipper's functions are run unchanged from a checkout of that commit (nothing of them is copied
here): ShaperCalibrate._get_shaper_smoothing (accel 5000 mm/s², square-corner velocity 5 mm/s,
and 2000 / 10000 mm/s² with 0 / 10 mm/s), ShaperCalibrate.find_shaper_max_accel (bisection to
1e-8 mm/s², target smoothing 0.12 mm) and shaper_defs.init_shaper for the shapers' impulses.

Run with Debian's Python (NumPy):
  /usr/bin/python3 tests/golden/gen_smoothing.py KLIPPER_CHECKOUT
Writes tests/golden/smoothing_klipper.csv: one row per shaper (zv, mzv, ei, 2hump_ei, 3hump_ei),
design frequency (20, 35.5, 50, 72.3, 110 Hz) and design damping (0.1, and 0.05 for zv, mzv, ei),
with Klipper's impulses (amplitudes and times, ';'-separated, full precision) and its figures.
"""
import csv
import os
import sys

import klipper_checkout  # tests/golden: the pinned commit and its sha256

KLIPPER_FILES = ["klippy/extras/shaper_calibrate.py", "klippy/extras/shaper_defs.py"]
SHAPERS = ["zv", "mzv", "ei", "2hump_ei", "3hump_ei"]
FREQUENCIES_HZ = [20.0, 35.5, 50.0, 72.3, 110.0]
SETTINGS = [(5000.0, 5.0), (2000.0, 0.0), (10000.0, 10.0)]  # (accel mm/s², scv mm/s)


def load_klipper(root):
    klipper_checkout.verify(root, KLIPPER_FILES)
    sys.path.insert(0, os.path.join(root, "klippy"))
    sys.path.insert(0, os.path.join(root, "klippy", "extras"))
    import importlib
    calibrate = importlib.import_module("extras.shaper_calibrate")
    defs = importlib.import_module("extras.shaper_defs")
    return calibrate.ShaperCalibrate(printer=None), defs


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: gen_smoothing.py KLIPPER_CHECKOUT")
    helper, defs = load_klipper(sys.argv[1])
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "smoothing_klipper.csv")
    fields = ["shaper", "frequency_hz", "damping_ratio", "amplitudes", "times_s"]
    for accel, scv in SETTINGS:
        fields.append(f"smoothing_mm_a{accel:g}_v{scv:g}")
    fields += ["max_accel_mm_s2_v5", "max_accel_mm_s2_v0", "max_accel_mm_s2_v10"]
    with open(out, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(fields)
        for name in SHAPERS:
            for zeta in ([0.1, 0.05] if name in ("zv", "mzv", "ei") else [0.1]):
                for freq in FREQUENCIES_HZ:
                    a, t = defs.init_shaper(name, freq, zeta)
                    row = [name, repr(freq), repr(zeta), ";".join(repr(x) for x in a), ";".join(repr(x) for x in t)]
                    for accel, scv in SETTINGS:
                        row.append(repr(helper._get_shaper_smoothing((a, t), accel=accel, scv=scv)))
                    for scv in (5.0, 0.0, 10.0):
                        row.append(repr(helper.find_shaper_max_accel((a, t), scv)))
                    w.writerow(row)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
