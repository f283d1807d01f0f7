#!/usr/bin/python3
"""Golden data for Eq. 5.1 with the band-entry start rule (tests/metrics/test_mean_deviation_golden.cpp).

Independent NumPy implementation of the definition in include/clearshape/metrics/mean_deviation.hpp:
M0 = mean of the final window; band b = max(k_noise * sigma_n, f_move * |M0 - s_first|) with sigma_n
from the mean square successive difference of the final window; the start k(M) is the earlier of
the first crossing of M and the first stay of `dwell` samples (or to the end) inside |s - M| <= b,
both after the departure (the first sample at half the largest |s - M|);
M and k iterated to a fixed point. Run with Debian's Python:
    /usr/bin/python3 tests/golden/gen_mean_deviation.py
Writes mean_deviation_signals.csv and mean_deviation_expected.json beside this script.
"""
import json
import os

import numpy as np
from scipy import signal

HERE = os.path.dirname(os.path.abspath(__file__))
TS = 1e-3
T = np.arange(0, 4001) * TS


def first_crossing(d):
    hit = (d == 0)
    hit[1:] |= np.sign(d[1:]) * np.sign(d[:-1]) < 0
    idx = np.flatnonzero(hit)
    return int(idx[0]) if idx.size else None


def first_band_entry(d, b, dwell):
    if b <= 0:
        return None
    inside = np.concatenate([[0], (np.abs(d) <= b).astype(np.int8), [0]])
    edges = np.diff(inside)
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)  # runs [start, end)
    ok = (ends - starts >= dwell) | (ends == d.size)
    return int(starts[ok][0]) if ok.any() else None


def mean_deviation(s, ts=TS, frac=0.2, search_from_s=-np.inf, k_noise=0.0, f_move=0.005,
                   dwell_s=0.1, band=None):
    n = s.size
    first = 0 if search_from_s <= 0 else min(int(np.ceil(search_from_s / ts - 1e-9)), n - 1)
    ws = max(first, n - min(max(int(np.ceil(frac * n)), 1), n))
    m = s[ws:].mean()
    tail = s[ws:]
    sigma = float(np.sqrt(np.sum(np.diff(tail) ** 2) / (2 * (tail.size - 1)))) if tail.size > 1 else 0.0
    b = max(k_noise * sigma, f_move * abs(m - s[first])) if band is None else band
    dwell = max(1, int(round(dwell_s / ts)))

    def meet(mean):
        d = s[first:] - mean
        big = np.abs(d).max()
        if not big > 0:
            return None
        j = int(np.flatnonzero(np.abs(d) >= 0.5 * big)[0])  # departure: half the largest excursion
        d = d[j:]
        c = first_crossing(d)
        e = first_band_entry(d, b, dwell)
        if e is not None and (c is None or e < c):
            return first + j + e, "band-entry"
        if c is not None:
            return first + j + c, "crossing"
        return None

    got = meet(m)
    k, rule = got if got else (ws, "window-start")
    seen, converged, it = [k], False, 0
    for it in range(1, 101):
        m = s[k:].mean()
        got = meet(m)
        k2, rule2 = got if got else (k, rule)
        if k2 == k:
            rule, converged = rule2, True
            break
        if k2 in seen:
            k, rule = k2, rule2
            m = s[k:].mean()
            break
        k, rule = k2, rule2
        seen.append(k)
    return {"mean_deviation": float(np.sqrt(np.mean((m - s[k:]) ** 2))), "steady_mean": float(m),
            "start_index": k, "start_rule": rule, "iterations": it, "converged": converged,
            "band_half_width": float(b), "noise_floor": sigma}


def step(num, den, t0=0.0):
    _, y = signal.step(signal.lti(num, den), T=T)
    shift = int(round(t0 / TS))
    return np.concatenate([np.zeros(shift), y[: T.size - shift]])


def main():
    rng = np.random.default_rng(20151121)
    wn = 2 * np.pi * 3.0
    ringing = step([wn**2], [1, 2 * 0.1 * wn, wn**2], t0=0.5)             # crosses its mean early
    drift = 0.01 * np.clip(T - 0.5, 0, None) / 3.5                          # slow sensor drift
    damped = step([wn**2], [1, 2 * 1.0 * wn, wn**2], t0=0.5) + drift       # one-sided approach
    damped_noisy = damped + rng.normal(0.0, 5e-4, T.size)                   # noise << band
    damped_loud = damped + rng.normal(0.0, 2e-2, T.size)                    # noise >> band
    shaped = step([wn**2], [1, 2 * 0.1 * wn, wn**2], t0=0.5)                # ZV-shaped: two half steps
    shaped = 0.5 * shaped + 0.5 * np.concatenate([np.zeros(int(round(0.5 / 3.0 / np.sqrt(1 - 0.01) / TS))), shaped])[: T.size]
    shaped = shaped - 0.004 * np.clip(T - 0.5, 0, None) / 3.5

    # The rate of the ringing step as a noise-free gyroscope reports it: 14.375 LSB per unit,
    # rounded; it rests at 0 (exactly its steady mean) before the move.
    rate = np.round(np.gradient(ringing, TS) * 14.375) / 14.375

    cols = {"time_s": T, "ringing": ringing, "damped": damped, "damped_noisy": damped_noisy,
            "damped_loud": damped_loud, "shaped": shaped, "quantized_rate": rate}
    names = list(cols)
    np.savetxt(os.path.join(HERE, "mean_deviation_signals.csv"), np.column_stack([cols[c] for c in names]),
               delimiter=",", header=",".join(names), comments="", fmt="%.17g")

    cases = []
    for name in names[1:]:
        cases.append({"signal": name, "options": {"search_from_s": 0.5}})
    cases += [
        {"signal": "damped", "options": {"search_from_s": 0.5, "band_half_width": 0.0}},
        {"signal": "damped", "options": {}},
        {"signal": "quantized_rate", "options": {}},  # rests on M = 0 before the move (departure)
        {"signal": "damped_noisy", "options": {"search_from_s": 0.5, "band_noise_multiple": 3.0}},
        {"signal": "damped_loud", "options": {"search_from_s": 0.5, "band_noise_multiple": 3.0}},
        {"signal": "shaped", "options": {"search_from_s": 0.5, "band_move_fraction": 0.002,
                                          "band_dwell_s": 0.02}},
    ]
    keymap = {"search_from_s": "search_from_s", "band_noise_multiple": "k_noise",
              "band_move_fraction": "f_move", "band_dwell_s": "dwell_s", "band_half_width": "band"}
    for c in cases:
        c["expected"] = mean_deviation(cols[c["signal"]], **{keymap[k]: v for k, v in c["options"].items()})
    with open(os.path.join(HERE, "mean_deviation_expected.json"), "w") as f:
        json.dump({"generator": "tests/golden/gen_mean_deviation.py", "sample_time_s": TS, "cases": cases},
                  f, indent=2)


if __name__ == "__main__":
    main()
