#!/usr/bin/python3
"""clearshape's pick against Klipper's own pick, both judged by Klipper's own estimate of the
remaining vibration (issue 20, item 1: on real Klipper spectra the pick leaves no more than
Klipper's pick + 1 point by Klipper's estimate).

Reference: Klipper (github.com/Klipper3d/klipper), commit 84104bbbd7625d28b4eaaad83f4562972460ecd9,
  scripts/calibrate_shaper.py        sha256 2b78173855a55a8968dfef8421551b630ad478df89df21e8444f42d5e0d49d44
  klippy/extras/shaper_calibrate.py  sha256 695d35f2d1f261109cbed3a8185a900bcce75f7cef1740920fec8a338701138c
  klippy/extras/shaper_defs.py       sha256 1d8627c8864f6ff683a160fece2197e00b1d4acb12bdd1d743a6a73b6b3f05fe
run unchanged from a checkout of that commit: calibrate_shaper.parse_log reads the file (and
normalises an accelerometer's PSD as Klipper does), calibrate_shaper.calibrate_shaper picks
(defaults: its five families, damping 0.1, scv 5), and ShaperCalibrate._estimate_remaining_vibrations,
worst over Klipper's test damping ratios on the bins up to 200 Hz, scores clearshape's picks from
their impulses (`clearshape recommend --json`, default rule and --weigh-smoothing klipper).

Usage (Debian's Python: NumPy, matplotlib):
  /usr/bin/python3 tests/golden/compare_klipper_pick.py KLIPPER_CHECKOUT CLEARSHAPE_BINARY FILE.csv [...]
Prints one line per file: Klipper's pick and clearshape's two picks with Klipper's estimate,
the smoothing and max acceleration, and the margin against Klipper's pick + 1 point.

  /usr/bin/python3 tests/golden/compare_klipper_pick.py --golden KLIPPER_CHECKOUT
writes, for the Klipper-format golden inputs (recommend_klipper_raw.csv, its PSD file and the three
synthetic printer spectra of gen_klipper_broad.py), what
tests/advise/test_klipper_pick.cpp compares with: Klipper's pick (name, frequency, impulses,
vibrations, smoothing, max_accel) in klipper_pick.json, and the PSD Klipper scores (normalised by
Klipper's parse_log, bins up to 200 Hz, full precision) as klipper_pick_<input>_scored.csv in
Klipper's PSD format (with its `shapers:` marker, so Klipper would read it as normalised).
"""
import contextlib
import io
import json
import os
import subprocess
import sys

import klipper_checkout  # tests/golden: the pinned commit and its sha256

KLIPPER_FILES = klipper_checkout.SHA256
MAX_FREQ_HZ = 200.0  # Klipper's MAX_FREQ, the bins calibrate_shaper scores


def load_klipper(root):
    klipper_checkout.verify(root, KLIPPER_FILES)
    sys.path.insert(0, os.path.join(root, "scripts"))
    import matplotlib
    matplotlib.use("Agg")
    import calibrate_shaper
    return calibrate_shaper


def klipper_estimate(helper, ratios, data, amplitudes, times):
    """Klipper's remaining vibration of a shaper: worst over its test damping ratios."""
    keep = data.freq_bins <= MAX_FREQ_HZ
    worst = 0.0
    for zeta in ratios:
        v, _ = helper._estimate_remaining_vibrations((amplitudes, times), zeta, data.freq_bins[keep], data.psd_sum[keep])
        worst = max(worst, v)
    return worst


def clearshape_pick(binary, path, extra):
    out = subprocess.run([binary, "recommend", "--data", path, "--json", *extra], capture_output=True, text=True)
    if out.returncode != 0:
        return None, out.stderr.strip().splitlines()[-1] if out.stderr else f"exit {out.returncode}"
    doc = json.loads(out.stdout)
    rec = doc["recommendation"]
    if rec is None:
        return None, doc["reason"]
    cand = next(c for c in doc["candidates"] if c["name"] == rec["name"])
    return cand, ""


GOLDEN_INPUTS = ["recommend_klipper_raw.csv", "recommend_klipper_raw_psd.csv",
                 "recommend_klipper_broad_psd.csv", "recommend_klipper_shoulders_psd.csv",
                 "recommend_klipper_narrow_psd.csv"]  # gen_klipper_broad.py


def klipper_pick(cs, path):
    with contextlib.redirect_stdout(io.StringIO()):
        name, all_shapers, _ = cs.calibrate_shaper(
            [cs.parse_log(path)], None, shapers=None, damping_ratio=None, scv=5.0, shaper_freqs=None,
            max_smoothing=None, max_vibrs_pcnt=None, test_damping_ratios=None, max_freq=MAX_FREQ_HZ)
    return next(s for s in all_shapers if s.name == name)


def write_golden(root):
    cs = load_klipper(root)
    here = os.path.dirname(os.path.abspath(__file__))
    cases = []
    for name in GOLDEN_INPUTS:
        data = cs.parse_log(os.path.join(here, name))
        k = klipper_pick(cs, os.path.join(here, name))
        amplitudes, times = cs.shaper_calibrate.shaper_defs.init_shaper(k.name, k.freq, 0.1)
        scored = f"klipper_pick_{os.path.splitext(name)[0]}_scored.csv"
        with open(os.path.join(here, scored), "w") as f:
            f.write(f"freq,psd_x,psd_y,psd_z,psd_xyz,shapers:,{k.name}({k.freq:.1f})\n")
            for i, freq in enumerate(data.freq_bins):
                if freq <= MAX_FREQ_HZ:
                    f.write(",".join(repr(float(x)) for x in (freq, data.psd_x[i], data.psd_y[i], data.psd_z[i],
                                                                data.psd_sum[i])) + ",,\n")
        cases.append({"input": name, "scored_psd": scored,
                      "test_damping_ratios": list(cs.shaper_calibrate.TEST_DAMPING_RATIOS),
                      "klipper_pick": {"name": k.name, "frequency_hz": float(k.freq), "vibrations": float(k.vibrs),
                                       "smoothing_mm": float(k.smoothing), "max_accel_mm_s2": float(k.max_accel),
                                       "amplitudes": [float(a) for a in amplitudes], "times_s": [float(t) for t in times]}})
    with open(os.path.join(here, "klipper_pick.json"), "w") as f:
        json.dump({"klipper_commit": "84104bbbd7625d28b4eaaad83f4562972460ecd9", "cases": cases}, f, indent=1)
        f.write("\n")
    print(f"wrote klipper_pick.json and {len(cases)} scored PSD files")


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "--golden":
        write_golden(sys.argv[2])
        return
    if len(sys.argv) < 4:
        sys.exit("usage: compare_klipper_pick.py KLIPPER_CHECKOUT CLEARSHAPE_BINARY FILE.csv [...]")
    cs = load_klipper(sys.argv[1])
    helper = cs.shaper_calibrate.ShaperCalibrate(printer=None)
    for path in sys.argv[3:]:
        data = cs.parse_log(path)
        k = klipper_pick(cs, path)
        line = [f"{os.path.basename(path)}: Klipper {k.name} {k.freq:.1f} Hz {100 * k.vibrs:.2f} % "
                f"(smoothing {k.smoothing:.3f}, max accel {k.max_accel:.0f})"]
        for label, extra in (("clearshape", []), ("clearshape --weigh-smoothing klipper", ["--weigh-smoothing", "klipper"])):
            cand, why = clearshape_pick(sys.argv[2], path, extra)
            if cand is None:
                line.append(f"{label}: no pick ({why})")
                continue
            a = [i["amplitude"] for i in cand["impulses"]]
            t = [i["time_s"] for i in cand["impulses"]]
            v = klipper_estimate(helper, cs.shaper_calibrate.TEST_DAMPING_RATIOS, data, a, t)
            line.append(f"{label} {cand['name']} {'+'.join(f'{f:.1f}' for f in cand['design_frequency_hz'])} Hz "
                        f"{100 * v:.2f} % by Klipper's estimate (smoothing {cand['smoothing_mm']:.3f}, max accel "
                        f"{cand['max_accel_mm_s2'] or 0:.0f}; {'within' if v <= k.vibrs + 0.01 else 'BEYOND'} Klipper + 1 point)")
        print("\n    ".join(line))


if __name__ == "__main__":
    main()
