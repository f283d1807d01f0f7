#!/usr/bin/python3
"""Golden data for shaping::on_update_grid: shapers on a drive's update grid, coded independently.

Writes tests/golden/grid_reference.json with, for each (method, f, zeta, grid_hz) case:
  designed   the impulses of the design (gen_shaping.py's independent NumPy/SciPy designs:
             ZV family, MZV, EI by continuation, SI by SLSQP);
  snapped    the impulses a drive that takes a new command only every T = 1/grid_hz seconds
             applies: each impulse on the update with integer index k = floor(t/T + 1/2) (t >= 0:
             the nearest update, halves up), impulses with the same k summed (math.fsum), at
             time k*T;
  v_designed, v_snapped   the residual vibration at the design mode, by the closed form
             V = exp(-zeta w t_N) * sqrt(C^2 + S^2) / sum(A),
             C = sum A_i exp(zeta w t_i) cos(wd t_i), S = the same with sin, wd = w sqrt(1 - zeta^2)
             (thesis Eq. 2.19; src/shaping/residual.cpp normalises by |sum A| the same way).
Every designed time is checked to lie at least 1e-6 T away from a half-update, so a rounding
difference in the design cannot move an impulse to the other update.
Run with Debian's python:  /usr/bin/python3 tests/golden/gen_grid.py
"""
import json
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gen_shaping as ref  # noqa: E402  (the independent designs)

TWO_PI = 2.0 * math.pi


def closed_form_v(a, t, f_hz, z):
    w = TWO_PI * f_hz
    wd = w * math.sqrt(1.0 - z * z)
    c = sum(ai * math.exp(z * w * ti) * math.cos(wd * ti) for ai, ti in zip(a, t))
    s = sum(ai * math.exp(z * w * ti) * math.sin(wd * ti) for ai, ti in zip(a, t))
    return math.exp(-z * w * t[-1]) * math.sqrt(c * c + s * s) / abs(math.fsum(a))


def snap(a, t, grid_hz):
    period = 1.0 / grid_hz
    groups = {}
    for ai, ti in zip(a, t):
        x = ti / period
        frac = x - math.floor(x)
        assert abs(frac - 0.5) > 1e-6, f"t = {ti} lies on a half-update of {grid_hz} Hz"
        k = int(math.floor(x + 0.5))
        groups.setdefault(k, []).append(float(ai))
    ks = sorted(groups)
    return [math.fsum(groups[k]) for k in ks], [k * period for k in ks], ks


def design(method, f_hz, z):
    if method in ("zv", "zvd", "zvdd"):
        return ref.zv_family(f_hz, z, {"zv": 0, "zvd": 1, "zvdd": 2}[method])
    if method == "mzv":
        return ref.mzv(f_hz, z)
    if method == "ei":
        return ref.ei_family("ei", f_hz, z, 0.05)
    if method == "si":  # V <= 5 % over +-20 % of the mode (the study's SI)
        a, t, _ = ref.si_design(0.8 * f_hz, 1.2 * f_hz, z, 0.05)
        return a, t
    raise ValueError(method)


def main():
    cases = []
    modes = [(14.955, 0.129, 30.0),  # the thesis rig's link mode on the drive's 30 Hz updates
             (3.32, 0.288, 30.0),    # a slow drive-side mode: several impulses per update span
             (10.0, 0.05, 100.0),
             (25.0, 0.03, 30.0),     # faster than the grid: impulses merge
             (40.0, 0.05, 30.0)]     # ZV collapses to one impulse (the identity)
    for f_hz, z, grid_hz in modes:
        for method in ("zv", "zvd", "zvdd", "mzv", "ei", "si"):
            a, t = design(method, f_hz, z)
            a, t = [float(x) for x in a], [float(x) for x in t]
            sa, st, ks = snap(a, t, grid_hz)
            cases.append({"method": method, "frequency_hz": f_hz, "zeta": z, "grid_hz": grid_hz,
                          "designed": {"times_s": t, "amplitudes": a},
                          "snapped": {"times_s": st, "amplitudes": sa, "update_index": ks},
                          "v_designed": closed_form_v(a, t, f_hz, z),
                          "v_snapped": closed_form_v(sa, st, f_hz, z)})
            print(f"{method:5s} {f_hz:7.3f} Hz z={z:5.3f} on {grid_hz:5.1f} Hz: {len(a)} -> {len(sa)} impulses, "
                  f"V {cases[-1]['v_designed']:.4f} -> {cases[-1]['v_snapped']:.4f}")
    out = {"generator": "tests/golden/gen_grid.py", "numpy": np.__version__, "cases": cases}
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "grid_reference.json")
    with open(path, "w") as fh:
        json.dump(out, fh, indent=1)
    print(f"wrote {path}: {len(cases)} cases")


if __name__ == "__main__":
    main()
