#!/usr/bin/python3
"""Golden data for clearshape's shaping module: an independent NumPy/SciPy implementation.

Writes tests/golden/shaping_reference.json with
  designs  impulses of zv/zvd/zvdd/zvddd/zv5d/mzv/ei/ei2/ei3/um-zv for several (f, zeta, vtol),
           V at the design point, and the insensitivity bands at 5 % and 10 %;
  curves   V(r) for r in [0, 2] at the design damping and at a mismatched damping;
  si       specified-insensitivity shapers (SLSQP) for several bands, with their duration.

Definitions (the same as clearshape's, coded independently from the formulas):
  V(w, z) = |sum A_i exp(-z w (t_N - t_i)) exp(j w sqrt(1 - z^2) t_i)| / sum A_i  (Eq. 2.19)
  ZV family: binomial amplitudes C(n+1, k) K^k at k pi / wd, K = exp(-z pi / sqrt(1 - z^2)).
  MZV: 1 : sqrt2 : 1 (undamped) at 0, 0.375 Td, 0.75 Td; k-th times Km^k,
       Km = exp(-0.75 z pi / sqrt(1 - z^2)).
  EI / EI2 / EI3: roots of the defining equations (zeros of V, humps of height Vtol with
       dV/dw = 0; see src/shaping/design_ei.cpp), by scipy.optimize.fsolve with continuation in
       zeta from Singhose's exact undamped closed forms.
  UM-ZV: amplitudes +1, -1, +1, times solving Eq. 2.20, continuation from [0, T/6, T/3].
  SI: minimise t_N s.t. V <= Vtol on the band, sum A = 1, A in [0, 1], by scipy SLSQP with the
      seed/continuation strategy of design_si.cpp (independent code, different SLSQP).
Run with Debian's python:  /usr/bin/python3 tests/golden/gen_shaping.py
"""
import json
import math
import os

import numpy as np
from scipy.optimize import brentq, fsolve, minimize

TWO_PI = 2.0 * math.pi


def phasor(a, t, w, z):
    a = np.asarray(a, float)
    t = np.asarray(t, float)
    w = np.atleast_1d(np.asarray(w, float))
    wd = w * math.sqrt(1.0 - z * z)
    terms = a * np.exp(-z * w[:, None] * (t[-1] - t)) * np.exp(1j * wd[:, None] * t)
    return terms.sum(axis=1)


def residual(a, t, w, z):
    return np.abs(phasor(a, t, w, z)) / abs(np.sum(a))


def dphasor(a, t, w, z):
    a = np.asarray(a, float)
    t = np.asarray(t, float)
    root = math.sqrt(1.0 - z * z)
    terms = a * np.exp(-z * w * (t[-1] - t)) * np.exp(1j * w * root * t)
    return np.sum((-z * (t[-1] - t) + 1j * root * t) * terms)


# ---------------------------------------------------------------- closed-form families
def zv_family(f_hz, z, n):
    wn = TWO_PI * f_hz
    k = math.exp(-z * math.pi / math.sqrt(1 - z * z))
    amps = np.array([math.comb(n + 1, i) * k**i for i in range(n + 2)])
    times = np.arange(n + 2) * math.pi / (wn * math.sqrt(1 - z * z))
    return amps / amps.sum(), times


def mzv(f_hz, z):
    td = 1.0 / (f_hz * math.sqrt(1 - z * z))
    km = math.exp(-0.75 * z * math.pi / math.sqrt(1 - z * z))
    a1 = 1 - 1 / math.sqrt(2)
    amps = np.array([a1, (math.sqrt(2) - 1) * km, a1 * km * km])
    return amps / amps.sum(), np.array([0.0, 0.375 * td, 0.75 * td])


# ---------------------------------------------------------------- EI family by continuation
def hump_system(n, zero_at_1, hump_at_1, nz, nh):
    def unpack(x):
        a = list(x[: n - 1]) + [1.0 - sum(x[: n - 1])]
        t = [0.0] + list(x[n - 1 : 2 * n - 2])
        return np.array(a), np.array(t)

    def eqs(x, z, vt):
        a, t = unpack(x)
        zeros = list(x[2 * n - 2 : 2 * n - 2 + nz]) + ([1.0] if zero_at_1 else [])
        humps = ([1.0] if hump_at_1 else []) + list(x[2 * n - 2 + nz :])
        out = []
        for r in zeros:
            p = phasor(a, t, TWO_PI * r, z)[0]
            out += [p.real, p.imag]
        for r in humps:
            p = phasor(a, t, TWO_PI * r, z)[0]
            out += [abs(p) - vt, 2 * (np.conj(p) * dphasor(a, t, TWO_PI * r, z)).real]
        return out

    def ok(x):
        a, t = unpack(x)
        return np.all(a > 0) and np.all(np.diff(t) > 0) and np.all(np.asarray(x[2 * n - 2 :]) > 0)

    return unpack, eqs, ok


def continuation(eqs, ok, x0, z_target, vt):
    x = np.array(x0, float)
    z = 0.0
    step = 0.01
    while z < z_target:
        nxt = min(z_target, z + step)
        sol = fsolve(eqs, x, args=(nxt, vt), xtol=1e-14, full_output=True)[0]
        if np.max(np.abs(eqs(sol, nxt, vt))) < 1e-11 and ok(sol):
            x, z, step = sol, nxt, min(0.01, 2 * step)
        else:
            step /= 2
            if step < 1e-5:
                return None
    return x


def ei_x0(vt):
    r1 = math.acos(-(1 - vt) / (1 + vt)) / math.pi
    return [(1 + vt) / 4, (1 - vt) / 2, 0.5, 1.0, r1, 2 - r1]


def ei2_x0(vt):
    big_x = (vt * vt * (math.sqrt(1 - vt * vt) + 1)) ** (1 / 3)
    a1 = (3 * big_x**2 + 2 * big_x + 3 * vt * vt) / (16 * big_x)
    rz = 2 / math.pi * math.acos(math.sqrt((8 * a1 - 1) / (8 * a1)))
    rh = 2 / math.pi * math.acos(math.sqrt((8 * a1 - 1) / (24 * a1)))
    return [a1, 0.5 - a1, 0.5 - a1, 0.5, 1.0, 1.5, rz, 2 - rz, rh, 2 - rh]


def ei3_x0(vt):
    a1 = (1 + 3 * vt + 2 * math.sqrt(2 * vt * (vt + 1))) / 16
    a2 = (1 - vt) / 4
    a3 = 1 - 2 * (a1 + a2)
    cs = np.sort(np.roots([4 * a1, 2 * a2, a3 - 2 * a1]).real)
    zeros = sorted([math.acos(c) / math.pi for c in cs] + [2 - math.acos(c) / math.pi for c in cs])
    rh = math.acos(-a2 / (4 * a1)) / math.pi
    return [a1, a2, a3, a2, 0.5, 1.0, 1.5, 2.0] + zeros + [rh, 2 - rh]


EI_SPECS = {
    "ei": ((3, False, True, 2, 0), ei_x0),
    "ei2": ((4, True, False, 2, 2), ei2_x0),
    "ei3": ((5, False, True, 4, 2), ei3_x0),
}


def ei_family(name, f_hz, z, vt):
    spec, x0f = EI_SPECS[name]
    unpack, eqs, ok = hump_system(*spec)
    x = continuation(eqs, ok, x0f(vt), z, vt)
    if x is None:
        return None
    a, t = unpack(x)
    return a / a.sum(), t / f_hz


def um_zv(f_hz, z):
    def eqs(x, zz, _):
        p = phasor([1, -1, 1], [0, x[0], x[1]], TWO_PI, zz)[0]
        return [p.real, p.imag]

    x = continuation(eqs, lambda x: 0 < x[0] < x[1], [1 / 6, 1 / 3], z, 0)
    return np.array([1.0, -1.0, 1.0]), np.array([0.0, x[0], x[1]]) / f_hz


# ---------------------------------------------------------------- insensitivity
def band(a, t, wm, z, vt):
    """Contiguous band of r around 1 with V <= vt: dense scan (1e-4) then brentq."""
    inside = vt * (1 + 1e-9)
    f = lambda r: residual(a, t, r * wm, z)[0] - inside
    if f(1.0) > 0:
        return 1.0, 1.0
    edges = []
    for direction in (-1, 1):
        r = np.arange(1, 10 if direction > 0 else 0, direction * 1e-4)
        v = residual(a, t, r * wm, z)
        out = np.nonzero(v > inside)[0]
        if len(out) == 0:
            edges.append(10.0)
            continue
        i = out[0]
        lo, hi = sorted((r[i - 1], r[i]))
        edges.append(brentq(f, lo, hi, xtol=1e-15))
    return edges[0], edges[1]


# ---------------------------------------------------------------- SI
def si_design(lo_hz, hi_hz, z, vt, points=60):
    ratio = hi_hz / lo_hz
    wc = TWO_PI * math.sqrt(lo_hz * hi_hz)
    # seeds at 1 Hz = period 1, scaled so the band is centred at rho = 1 (times in rad / wc)
    cands = []
    makers = [("zv", lambda: zv_family(1 / TWO_PI, z, 0))]
    for name in ("ei", "ei2", "ei3"):
        makers.append((name, lambda name=name: ei_family(name, 1 / TWO_PI, z, vt)))
    for name, mk in makers:
        d = mk()
        if d is None:
            continue
        lo, hi = band(d[0], d[1], 1.0, z, vt)
        cands.append((d[0], d[1] * math.sqrt(lo * hi), hi / lo))
    if len(cands) < 4:
        for n in (1, 2, 3):
            a, t = zv_family(1 / TWO_PI, z, n)
            lo, hi = band(a, t, 1.0, z, vt)
            cands.append((a, t * math.sqrt(lo * hi), hi / lo))
    covering = [c for c in cands if c[2] >= ratio]
    seed = min(covering, key=lambda c: c[1][-1]) if covering else max(cands, key=lambda c: c[2])
    a, t = seed[0].copy(), seed[1].copy()

    def solve(a, t, r):
        n = len(a)
        rho = np.linspace(1 / math.sqrt(r), math.sqrt(r), points)
        dense = np.linspace(1 / math.sqrt(r), math.sqrt(r), 20001)
        target = vt * (1 - 1e-4)

        def unpack(x):
            return x[:n], np.concatenate([[0.0], np.cumsum(x[n:])])

        x = np.concatenate([a, np.diff(t)])
        for _ in range(10):  # add the dense-grid peaks above vt to the constraint set
            def cons(x, rho=rho):
                aa, tt = unpack(x)
                return 1 - (np.abs(phasor(aa, tt, rho, z)) / (target * aa.sum())) ** 2

            x = minimize(lambda x: x[n:].sum(), x, jac=lambda x: np.r_[np.zeros(n), np.ones(n - 1)],
                         method="SLSQP", bounds=[(0, 1)] * n + [(0, None)] * (n - 1),
                         constraints=[{"type": "eq", "fun": lambda x: x[:n].sum() - 1},
                                      {"type": "ineq", "fun": cons}],
                         options={"ftol": 1e-14, "maxiter": 3000}).x
            aa, tt = unpack(x)
            aa = np.clip(aa, 0, None) / np.clip(aa, 0, None).sum()
            v = residual(aa, tt, dense, z)
            peaks = [i for i in range(len(v)) if v[i] > vt * (1 + 1e-9)
                     and (i == 0 or v[i] >= v[i - 1]) and (i + 1 == len(v) or v[i] >= v[i + 1])]
            if not peaks or np.max(residual(aa, tt, rho, z)) > vt * (1 + 1e-6):
                break
            rho = np.r_[rho, dense[peaks]]
        return aa, tt, v.max()

    def split(a, t):
        k = int(np.argmax(a))
        lo = max(t[k] - 0.01, 0.5 * (t[k - 1] + t[k]) if k > 0 else 0.0)
        hi = min(lo + 0.02, 0.5 * (t[k] + t[k + 1]) if k + 1 < len(a) else lo + 0.02)
        return (np.r_[a[:k], a[k] / 2, a[k] / 2, a[k + 1 :]], np.r_[t[:k], lo, hi, t[k + 1 :]])

    log_r, log_target, step, splits = math.log(seed[2]), math.log(ratio), 0.05, 0
    while True:
        nxt = min(log_target, log_r + step) if log_r < log_target else max(log_target, log_r - step)
        aa, tt, vmax = solve(a, t, math.exp(nxt))
        if vmax <= vt * (1 + 1e-6) and tt[-1] <= 1.25 * t[-1] + 1e-9:
            a, t, log_r, splits, step = aa, tt, nxt, 0, min(0.05, 2 * step)
            if nxt == log_target:
                break
        elif splits < 2:
            a, t = split(a, t)
            splits += 1
        else:
            step /= 2
            assert step > 1e-3, "SI continuation failed"
    keep = a > 1e-12
    return a[keep], (t[keep] - t[keep][0]) / wc, vmax


# ---------------------------------------------------------------- assemble
def design_entry(method, f_hz, z, vt, a, t):
    wm = TWO_PI * f_hz
    b5 = band(a, t, wm, z, 0.05)
    b10 = band(a, t, wm, z, 0.10)
    return {"method": method, "frequency_hz": f_hz, "zeta": z, "vtol": vt,
            "times_s": list(map(float, t)), "amplitudes": list(map(float, a)),
            "v_design": float(residual(a, t, wm, z)[0]),
            "band_5": [float(b5[0]), float(b5[1])], "band_10": [float(b10[0]), float(b10[1])]}


def main():
    designs = []
    grid = [(10.0, 0.0), (10.0, 0.05), (10.0, 0.1), (3.7, 0.2), (1.3, 0.35), (25.0, 0.03)]
    for f_hz, z in grid:
        for name, n in (("zv", 0), ("zvd", 1), ("zvdd", 2), ("zvddd", 3), ("zv5d", 5)):
            a, t = zv_family(f_hz, z, n)
            designs.append(design_entry(name, f_hz, z, 0.05, a, t))
        a, t = mzv(f_hz, z)
        designs.append(design_entry("mzv", f_hz, z, 0.05, a, t))
        for name in ("ei", "ei2", "ei3"):
            d = ei_family(name, f_hz, z, 0.05)
            if d is not None:
                designs.append(design_entry(name, f_hz, z, 0.05, *d))
        a, t = um_zv(f_hz, z)
        designs.append(design_entry("um-zv", f_hz, z, 0.05, a, t))
    for name, f_hz, z, vt in (("ei", 10.0, 0.1, 0.02), ("ei", 6.0, 0.3, 0.1), ("ei2", 10.0, 0.05, 0.1),
                              ("ei3", 8.0, 0.15, 0.03), ("ei", 10.0, 0.0, 0.2)):
        designs.append(design_entry(name, f_hz, z, vt, *ei_family(name, f_hz, z, vt)))

    curves = []
    r = np.linspace(0.0, 2.0, 81)
    for d in designs:
        if (d["frequency_hz"], d["zeta"]) not in ((10.0, 0.1), (3.7, 0.2)) or d["vtol"] != 0.05:
            continue
        a, t = np.array(d["amplitudes"]), np.array(d["times_s"])
        wm = TWO_PI * d["frequency_hz"]
        for actual in (d["zeta"], 0.5 * d["zeta"] + 0.02):
            curves.append({"method": d["method"], "frequency_hz": d["frequency_hz"], "zeta": d["zeta"],
                           "actual_zeta": actual, "ratios": list(map(float, r)),
                           "residual": list(map(float, residual(a, t, r * wm, actual)))})

    si = []
    for lo, hi, z, vt in ((8.0, 12.0, 0.0, 0.05), (7.0, 13.0, 0.1, 0.05), (9.0, 11.0, 0.05, 0.05),
                          (5.0, 15.0, 0.1, 0.05), (6.0, 14.0, 0.0, 0.02), (2.4, 3.6, 0.2, 0.1),
                          (3.0, 17.0, 0.05, 0.05)):
        a, t, vmax = si_design(lo, hi, z, vt)
        si.append({"band_low_hz": lo, "band_high_hz": hi, "zeta": z, "vtol": vt,
                   "times_s": list(map(float, t)), "amplitudes": list(map(float, a)),
                   "duration_s": float(t[-1]), "max_v": float(vmax)})
        print(f"si {lo}-{hi} z={z} vt={vt}: {len(a)} impulses, duration {t[-1]:.6f} s, max V {vmax:.6f}")

    out = {"generator": "tests/golden/gen_shaping.py", "numpy": np.__version__,
           "designs": designs, "curves": curves, "si": si}
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "shaping_reference.json")
    with open(path, "w") as fh:
        json.dump(out, fh, indent=1)
    print(f"wrote {path}: {len(designs)} designs, {len(curves)} curves, {len(si)} SI cases")


if __name__ == "__main__":
    main()
