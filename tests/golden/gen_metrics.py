#!/usr/bin/python3
"""Golden data for the metrics module (tests/metrics/test_golden.cpp).

Independent NumPy/SciPy implementation of the definitions documented in
include/clearshape/metrics/*.hpp: stepinfo-like specs (MATLAB stepinfo definitions), Eq. 5.1
mean deviation with the first-coincidence start rule, Eq. 4.1 consistency errors, NRMSE fit.
Run with Debian's Python:  /usr/bin/python3 tests/golden/gen_metrics.py
Writes metrics_signals.csv and metrics_expected.json beside this script.
"""
import json
import os

import numpy as np
from scipy import signal

HERE = os.path.dirname(os.path.abspath(__file__))
TS = 1e-3
T = np.arange(0, 3001) * TS


def step(num, den):
    _, y = signal.step(signal.lti(num, den), T=T)
    return y


def interp_cross(y, level, sign):
    """First time (in samples) y reaches level in direction sign, linearly interpolated."""
    hit = np.nonzero(sign * (y - level) >= 0)[0]
    if hit.size == 0:
        return np.nan
    i = hit[0]
    if i == 0:
        return 0.0
    a, b = y[i - 1] - level, y[i] - level
    return (i - 1) + a / (a - b)


def stepinfo(y, yfinal=None, yinit=0.0, st=0.02, lo=0.1, hi=0.9):
    yf = y[-1] if yfinal is None else yfinal
    d = yf - yinit
    sgn = np.sign(d)
    h = abs(d)
    t_lo = interp_cross(y, yinit + lo * d, sgn)
    t_hi = interp_cross(y, yinit + hi * d, sgn)
    out = np.abs(y - yf) > st * h
    idx = np.nonzero(out)[0]
    if idx.size == 0:
        settle = 0.0
    elif idx[-1] == y.size - 1:
        settle = np.nan
    else:
        j = idx[-1]
        a = abs(y[j] - yf) - st * h
        b = abs(y[j + 1] - yf) - st * h
        settle = (j + a / (a - b)) * TS
    first = int(np.ceil(t_hi - 1e-12))
    ex = sgn * (y - yinit)
    pk = int(np.argmax(np.abs(y - yinit)))
    return {
        "rise_time_s": (t_hi - t_lo) * TS,
        "settling_time_s": settle,
        "settling_min": float(y[first:].min()),
        "settling_max": float(y[first:].max()),
        "overshoot_percent": 100 * max(0.0, ex.max() - h) / h,
        "undershoot_percent": 100 * max(0.0, -ex.min()) / h,
        "peak": float(abs(y[pk] - yinit)),
        "peak_time_s": pk * TS,
        "final_value": float(yf),
    }


def coincide(s, m):
    d = s - m
    zero = np.nonzero(d == 0)[0]
    change = np.nonzero(d[1:] * d[:-1] < 0)[0] + 1
    cand = np.concatenate([zero, change])
    return int(cand.min()) if cand.size else None


def mean_deviation(s, frac=0.2):
    n = s.size
    w = int(np.ceil(frac * n))
    m = s[n - w:].mean()
    k = coincide(s, m)
    seen = [k]
    for it in range(1, 101):
        m = s[k:].mean()
        k2 = coincide(s, m)
        if k2 == k:
            break
        k = k2
        seen.append(k)
    md = np.sqrt(np.mean((m - s[k:]) ** 2))
    return {"mean_deviation": md, "steady_mean": m, "start_index": k, "iterations": it}


def main():
    wn = 2 * np.pi * 3.0
    z = 0.1
    second = step([wn**2], [1, 2 * z * wn, wn**2])
    # Thesis Eq. 4.2, speed mode: K(1+Tz s)/((1+2ζTw s+(Tw s)^2)(1+Tp3 s)); negative Tz -> undershoot.
    K, Tz, zeta, Tw, Tp3 = 25.47, -0.0398, 0.2880, 0.0479, 0.0857
    den = np.polymul([Tw**2, 2 * zeta * Tw, 1], [Tp3, 1])
    thesis = step([K * Tz, K], den)
    rng = np.random.default_rng(20150101)
    noisy = second + rng.normal(0.0, 0.01, T.size)
    model = step([(2 * np.pi * 3.2) ** 2], [1, 2 * 0.15 * 2 * np.pi * 3.2, (2 * np.pi * 3.2) ** 2])
    runs = [second + rng.normal(0.0, 0.005, T.size) for _ in range(4)]

    cols = {"time_s": T, "second_order": second, "thesis_speed": thesis, "noisy": noisy,
            "model": model}
    for i, r in enumerate(runs):
        cols[f"run{i + 1}"] = r
    names = list(cols)
    data = np.column_stack([cols[c] for c in names])
    np.savetxt(os.path.join(HERE, "metrics_signals.csv"), data, delimiter=",",
               header=",".join(names), comments="", fmt="%.17g")

    mean_sig = np.mean(runs, axis=0)
    r = mean_sig.max() - mean_sig.min()
    errors = [float(np.sqrt(np.mean((mean_sig - x) ** 2)) / r) for x in runs]

    def fit(y, yh):
        return 100 * (1 - np.linalg.norm(y - yh) / np.linalg.norm(y - y.mean()))

    expected = {
        "generator": "tests/golden/gen_metrics.py",
        "sample_time_s": TS,
        "stepinfo": {
            "second_order": stepinfo(second),
            "second_order_yfinal1": stepinfo(second, yfinal=1.0),
            "thesis_speed": stepinfo(thesis, yfinal=K),
        },
        "mean_deviation": {
            "second_order": mean_deviation(second),
            "noisy": mean_deviation(noisy),
        },
        "consistency": {"errors": errors, "mean_error": float(np.mean(errors)), "range": r},
        "fit_percent": fit(second, model),
        "rmse": float(np.sqrt(np.mean((second - model) ** 2))),
    }
    with open(os.path.join(HERE, "metrics_expected.json"), "w") as f:
        json.dump(expected, f, indent=2, default=float)


if __name__ == "__main__":
    main()
