#!/usr/bin/python3
"""Golden data for the stabilisation diagram (ident/stabilisation.hpp), from an independent NumPy
implementation of ERA and of the diagram's rules.

Run with Debian's Python (numpy):  /usr/bin/python3 tests/golden/gen_stabilisation.py
Writes (small, committed; CI never regenerates them):
  stabilisation_free_decay.csv   three damped sinusoids + offset + white noise (seed 21), 1 kHz
  stabilisation_expected.json    truth, the diagram (stable poles per order), persistent modes,
                                 chosen order

ERA (Ho & Kalman 1966; Juang & Pappa 1985): Hankel matrix of 96 rows, SVD, Γ = U₁S₁^½, A by least
squares on Γ's shift invariance, x0 = S₁^½V₁ᵀe₁, at every order 2…24. A pole pair z gives
s = ln z / T, ωn = |s|, ζ = −Re s/|s|. Stability against the previous order's nearest pole:
|Δf|/f < 1 %, |Δζ|/ζ < 5 % and 0 < ζ < 0.7 (Peeters & De Roeck 2001). A persistent mode is a
chain of stable poles (each with a residue ≥ 5 % of its order's largest) closer than 1 % holding
≥ 5 orders and ≥ 70 % of the orders from its first one up; the chosen order is the lowest holding
every persistent mode as a stable pole.
"""
import json
import os

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
DT = 1e-3
ROWS = 96
ORDERS = range(2, 25)
F_TOL, Z_TOL, MAX_ZETA, MIN_ORDERS, MIN_FRACTION, MIN_AMPLITUDE = 0.01, 0.05, 0.7, 5, 0.7, 0.05
MODES = [(30.0, 0.02, 10.0, 0.3), (75.0, 0.01, 5.0, -0.7), (160.0, 0.005, 3.0, 1.1)]


def record():
    n = 1500
    t = np.arange(n) * DT
    y = 0.5 + sum(a * np.exp(-z * 2 * np.pi * f * t) * np.cos(2 * np.pi * f * np.sqrt(1 - z * z) * t + ph)
                  for f, z, a, ph in MODES)
    rng = np.random.default_rng(21)
    return t, y + 0.05 * rng.standard_normal(n)


def era_poles(y, order):
    cols = len(y) - ROWS + 1
    h = np.array([y[r:r + cols] for r in range(ROWS)])
    u, s, vt = np.linalg.svd(h, full_matrices=False)
    g = u[:, :order] * np.sqrt(s[:order])
    a = np.linalg.lstsq(g[:-1], g[1:], rcond=None)[0]
    x0 = np.sqrt(s[:order]) * vt[:order, 0]
    lam, w = np.linalg.eig(a)
    weights = np.linalg.solve(w, x0)
    poles = []
    for k, z in enumerate(lam):
        if z.imag <= 1e-10 * max(1.0, abs(z)) or np.angle(z) >= 0.9 * np.pi:
            continue
        sp = np.log(z) / DT
        poles.append({"wn": abs(sp), "zeta": -sp.real / abs(sp), "amplitude": 2 * abs((g[0] @ w[:, k]) * weights[k])})
    return sorted(poles, key=lambda p: p["wn"])


def flag(orders):
    for prev, now in zip(orders, orders[1:]):
        for p in now["poles"]:
            q = min(prev["poles"], key=lambda q: abs(q["wn"] - p["wn"]), default=None)
            p["stable"] = bool(q is not None and abs(p["wn"] - q["wn"]) / q["wn"] < F_TOL
                               and abs(p["zeta"] - q["zeta"]) / abs(q["zeta"]) < Z_TOL and 0 < p["zeta"] < MAX_ZETA)
    for p in orders[0]["poles"]:
        p["stable"] = False


def persistent(orders):
    stable = []
    for o in orders:
        largest = max((p["amplitude"] for p in o["poles"]), default=0.0)
        stable += [(p["wn"], p["zeta"], o["order"]) for p in o["poles"] if p["stable"] and p["amplitude"] >= MIN_AMPLITUDE * largest]
    stable.sort()
    chains, cur = [], []
    for s in stable:
        if cur and abs(s[0] - cur[-1][0]) / cur[-1][0] >= F_TOL:
            chains.append(cur)
            cur = []
        cur.append(s)
    if cur:
        chains.append(cur)
    modes = []
    for c in chains:
        in_orders = sorted({s[2] for s in c})
        span = sum(1 for o in orders if o["order"] >= in_orders[0])
        if len(in_orders) >= MIN_ORDERS and len(in_orders) >= MIN_FRACTION * span:
            modes.append({"wn": float(np.median([s[0] for s in c])), "zeta": float(np.median([s[1] for s in c])),
                          "stable_orders": len(in_orders)})
    return modes


def chosen(orders, modes):
    best, best_count = 0, 0
    for o in orders:
        count = sum(any(p["stable"] and abs(p["wn"] - m["wn"]) <= F_TOL * m["wn"] for p in o["poles"]) for m in modes)
        if count > best_count:
            best, best_count = o["order"], count
        if count == len(modes):
            break
    return best


def main():
    t, y = record()
    np.savetxt(os.path.join(HERE, "stabilisation_free_decay.csv"), np.c_[t, y], delimiter=",",
               header="time_s,link_rate_deg_s", comments="", fmt="%.17g")
    orders = [{"order": n, "poles": era_poles(y, n)} for n in ORDERS]
    flag(orders)
    modes = persistent(orders)
    out = {
        "generator": "tests/golden/gen_stabilisation.py (numpy %s)" % np.__version__,
        "truth": [{"frequency_hz": f, "damping_ratio": z, "amplitude": a} for f, z, a, _ in MODES],
        "tolerances": {"frequency": F_TOL, "damping": Z_TOL, "min_stable_orders": MIN_ORDERS,
                       "min_stable_fraction": MIN_FRACTION, "min_relative_amplitude": MIN_AMPLITUDE,
                       "hankel_rows": ROWS},
        "orders": [{"order": o["order"], "poles": [{"frequency_hz": p["wn"] / (2 * np.pi), "damping_ratio": p["zeta"],
                                                    "stable": p["stable"]} for p in o["poles"]]} for o in orders],
        "persistent_modes": [{"frequency_hz": m["wn"] / (2 * np.pi), "damping_ratio": m["zeta"],
                              "stable_orders": m["stable_orders"]} for m in modes],
        "chosen_order": chosen(orders, modes),
    }
    with open(os.path.join(HERE, "stabilisation_expected.json"), "w") as f:
        json.dump(out, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
