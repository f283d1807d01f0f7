#!/usr/bin/python3
"""Golden data for the lti module, from SciPy (run with /usr/bin/python3; numpy + scipy).

For each process model G(s) = Kp (1+Tz s)/den(s) e^(-Td s) [/s] the transfer function is
expanded here independently (numpy.polymul of the factors), then SciPy provides:
  tf2ss (A, B, C, D), poles/zeros (numpy.roots), freqresp (times e^(-jwTd)),
  cont2discrete zoh/foh, step, and lsim (interp=False <-> ZOH, interp=True <-> FOH).
Delays: integer-sample delays shift the input; fractional delays Td = (d + p/M) T are
simulated by lsim on a grid M times finer, on which the delayed held (ZOH) or linearly
interpolated (FOH) input is represented exactly, then subsampled.
Writes tests/golden/lti_<case>.json. Usage: /usr/bin/python3 tests/golden/gen_lti.py
"""
import json
import os
from fractions import Fraction

import numpy as np
import scipy
from scipy import signal

HERE = os.path.dirname(os.path.abspath(__file__))
DT = 1e-3
DURATION = 1.0

CASES = [
    # name, structure, parameters
    ("speed", "P3UZ", dict(Kp=25.47, Tz=-0.0398, Zeta=0.2880, Tw=0.0479, Tp3=0.0857)),
    ("position", "P3UZ", dict(Kp=0.9959, Tz=0.0042, Zeta=0.9968, Tw=0.0102, Tp3=0.0034)),
    ("p1d_int", "P1D", dict(Kp=2.0, Tp1=0.05, Td=0.004)),
    ("p1d_frac", "P1D", dict(Kp=2.0, Tp1=0.05, Td=0.0125)),
    ("p2", "P2", dict(Kp=1.3, Tp1=0.2, Tp2=0.01)),
    ("p2i", "P2I", dict(Kp=0.8, Tp1=0.1, Tp2=0.02)),
    ("p2u", "P2U", dict(Kp=1.0, Tw=0.02, Zeta=0.05)),
    ("p3dzu_frac", "P3DZU", dict(Kp=-3.0, Tp3=0.3, Tw=0.01, Zeta=0.4, Td=0.00725, Tz=0.05)),
    ("p3z_wide", "P3Z", dict(Kp=3.0, Tp1=1e-4, Tp2=0.5, Tp3=2.0, Tz=0.02)),
]


def expand(structure, p):
    """Numerator and denominator in descending powers of s (independent of the C++ code)."""
    num = np.array([p["Kp"]])
    if "Z" in structure:
        num = np.polymul(num, [p["Tz"], 1.0])
    den = np.array([1.0])
    for name in ("Tp1", "Tp2", "Tp3"):
        if name in p:
            den = np.polymul(den, [p[name], 1.0])
    if "U" in structure:
        den = np.polymul(den, [p["Tw"] ** 2, 2.0 * p["Zeta"] * p["Tw"], 1.0])
    if "I" in structure:
        den = np.polymul(den, [1.0, 0.0])
    return num, den


def test_input(n):
    """Deterministic rich input: seeded random levels held 25 samples + sine + ramp; u[0] = 0."""
    rng = np.random.default_rng(20150601)
    t = np.arange(n) * DT
    levels = rng.choice([-1.0, 1.0], size=n // 25 + 1)
    u = np.repeat(levels, 25)[:n] + 0.5 * np.sin(2 * np.pi * 2.0 * t) + np.clip(t - 0.6, 0, None) * 3.0
    u[0] = 0.0
    return u


def delayed_lsim(sys, u, td, interp):
    """lsim of the input delayed by td (exact for the held/interpolated input)."""
    frac = Fraction(td / DT).limit_denominator(1000)
    assert abs(float(frac) - td / DT) < 1e-12
    m = frac.denominator
    shift = frac.numerator  # in fine samples
    n = len(u)
    h = DT / m
    nf = (n - 1) * m + 1
    tf_ = np.arange(nf) * h
    t = np.arange(n) * DT
    if interp:
        uf = np.interp(tf_, t, u)
    else:
        uf = np.repeat(u, m)[:nf]
    ud = np.concatenate([np.zeros(shift), uf])[:nf]
    _, y, _ = signal.lsim(sys, ud, tf_, interp=interp)
    return np.atleast_1d(y)[::m]


def markov(a, b, c, d, count=12):
    out = [float(d[0, 0])]
    x = b
    for _ in range(count - 1):
        out.append(float((c @ x)[0, 0]))
        x = a @ x
    return out


def cplx(values):
    return [[float(np.real(v)), float(np.imag(v))] for v in values]


def main():
    n = int(round(DURATION / DT)) + 1
    t = np.arange(n) * DT
    u = test_input(n)
    omega = np.logspace(-1, 4, 41)
    for name, structure, p in CASES:
        num, den = expand(structure, p)
        td = p.get("Td", 0.0)
        sys = signal.lti(num, den)
        a, b, c, d = signal.tf2ss(num, den)
        doc = {
            "generator": "tests/golden/gen_lti.py",
            "scipy_version": scipy.__version__,
            "case": name,
            "structure": structure,
            "parameters": p,
            "num": num.tolist(),
            "den": den.tolist(),
            "tf2ss": {"a": a.tolist(), "b": b.tolist(), "c": c.tolist(), "d": d.tolist()},
            "poles": cplx(sorted(np.roots(den), key=lambda z: (z.real, z.imag))),
            "zeros": cplx(sorted(np.roots(num), key=lambda z: (z.real, z.imag))) if len(num) > 1 else [],
        }
        _, h = signal.freqresp(sys, w=omega)
        h = h * np.exp(-1j * omega * td)
        doc["freqresp"] = {"omega_rad_s": omega.tolist(), "h": cplx(h)}
        disc = {}
        for dt in (1e-3, 1e-2):
            for method in ("zoh", "foh"):
                ad, bd, cd, dd, _ = signal.cont2discrete((a, b, c, d), dt, method=method)
                disc[f"{method}_{dt:g}"] = {"sample_time_s": dt, "method": method, "a": ad.tolist(),
                                            "b": bd.tolist(), "c": cd.tolist(), "d": dd.tolist(),
                                            "markov": markov(ad, bd, cd, dd)}
        doc["cont2discrete"] = disc
        # Step of amplitude 1 at t = 0 (delay included).
        if td == 0.0:
            _, ys = signal.step(sys, T=t)
        else:
            ys = delayed_lsim(sys, np.ones(n), td, interp=False)
        doc["step"] = {"sample_time_s": DT, "y": np.atleast_1d(ys).tolist()}
        # lsim with the rich input.
        sims = {"sample_time_s": DT, "u": u.tolist()}
        for key, interp in (("zoh", False), ("foh", True)):
            if td == 0.0:
                _, y, _ = signal.lsim(sys, u, t, interp=interp)
            else:
                y = delayed_lsim(sys, u, td, interp)
            sims[key] = np.atleast_1d(y).tolist()
        if td == 0.0:
            x0 = np.linspace(1.0, -0.5, a.shape[0])
            _, y, _ = signal.lsim((a, b, c, d), u, t, X0=x0, interp=True)
            sims["foh_x0"] = {"x0": x0.tolist(), "y": np.atleast_1d(y).tolist()}
        doc["lsim"] = sims
        path = os.path.join(HERE, f"lti_{name}.json")
        with open(path, "w") as fh:
            json.dump(doc, fh, indent=None, separators=(",", ":"))
            fh.write("\n")
        print(f"{path}: {os.path.getsize(path)} bytes")


if __name__ == "__main__":
    main()
