#!/usr/bin/python3
"""Synthetic Klipper TEST_RESONANCES PSD files of the broad multi-peak shape on which clearshape's
pick left more than Klipper's + 1 point by Klipper's estimate on real printers' files (issue 20;
docs/recommend.md, "On real printers' spectra"). The real files may not be redistributed; these
reproduce their shape from a stated model, seeded.

Model: the printer's response per unit of excitation is a floor plus modes, each mode's power
h·(2ζ)² / ((1 − r²)² + (2ζr)²), r = f / fn (peak h at fn, half-power width 2ζ·fn), scattered as a
Welch average of 20 segments (χ² with 40 degrees of freedom / 40). TEST_RESONANCES drives the axis
at an acceleration proportional to f (Klipper's resonance_tester.py: accel = accel_per_hz · freq),
and Klipper's calibrate_shaper divides the file's PSD by f + 0.1 Hz again (parse_log,
normalize_to_frequencies): the file holds the response × (f + 0.1 Hz). Bins every 1.6377 Hz up to
200 Hz (a 1000 Hz accelerometer's 610-sample segments: Klipper's own files are 1.5–1.7 Hz apart),
written as Klipper's save_calibration_data writes them ("%.1f,%.3e,%.3e,%.3e,%.3e"; psd_xyz the
sum of the three, x and z 10 % each).

  recommend_klipper_broad_psd.csv: a broad 31 Hz mode, the file's highest, once normalised, and a
    cluster at 63, 83.5 (narrow) and 90 Hz that is the file's highest as written.
  recommend_klipper_shoulders_psd.csv: the same kind with a cluster at 60, 68, 83.5 (narrow) and
    89 Hz, whose one line fitted down to 10 % of the 83.5 Hz peak is shouldered (ζ 0.28 against
    its half-power band's 0.06).
  recommend_klipper_narrow_psd.csv: a broad 28 Hz mode and a cluster at 60, 72, 85 (unresolved:
    two bins wide) and 92 Hz, found as two modes of ζ 0.007 and 0.25; Klipper's score
    (--weigh-smoothing klipper) picked a short MZV leaving 46 % there (test_recommend_smoothing.cpp).

Run with Debian's Python (NumPy):
  /usr/bin/python3 tests/golden/gen_klipper_broad.py
then /usr/bin/python3 tests/golden/compare_klipper_pick.py --golden KLIPPER_CHECKOUT for
Klipper's picks on them (klipper_pick.json).
"""
import os

import numpy as np

BIN_HZ = 1.6377
MAX_FREQ_HZ = 200.0
CASES = {
    # name: (modes as (fn Hz, ζ, peak power), floor, seed)
    "recommend_klipper_broad_psd.csv": ([(31.0, 0.10, 1.0), (63.0, 0.10, 0.40), (83.5, 0.025, 0.55), (90.0, 0.05, 0.2)], 0.01, 1),
    "recommend_klipper_shoulders_psd.csv": (
        [(31.0, 0.12, 1.0), (60.0, 0.12, 0.35), (68.0, 0.10, 0.3), (83.5, 0.02, 0.6), (89.0, 0.04, 0.3)], 0.01, 3),
    "recommend_klipper_narrow_psd.csv": (
        [(28.0, 0.15, 1.0), (60.0, 0.12, 0.4), (72.0, 0.10, 0.4), (85.0, 0.02, 0.7), (92.0, 0.04, 0.3)], 0.01, 2),
}


def response(f, modes, floor):
    """The response per unit of excitation: floor + Σ h·(2ζ)² / ((1 − r²)² + (2ζr)²)."""
    out = np.full_like(f, floor)
    for fn, zeta, height in modes:
        r = f / fn
        out += height * (2.0 * zeta) ** 2 / ((1.0 - r**2) ** 2 + (2.0 * zeta * r) ** 2)
    return out


def write(path, modes, floor, seed):
    rng = np.random.default_rng(seed)
    f = np.arange(0.0, MAX_FREQ_HZ, BIN_HZ)
    power = response(f, modes, floor) * rng.chisquare(40, f.size) / 40.0 * (f + 0.1)
    with open(path, "w") as out:
        out.write("freq,psd_x,psd_y,psd_z,psd_xyz\n")
        for fi, p in zip(f, power):
            out.write("%.1f,%.3e,%.3e,%.3e,%.3e\n" % (fi, 0.1 * p, 0.8 * p, 0.1 * p, p))


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    for name, (modes, floor, seed) in CASES.items():
        write(os.path.join(here, name), modes, floor, seed)
        print(f"wrote {name}")


if __name__ == "__main__":
    main()
