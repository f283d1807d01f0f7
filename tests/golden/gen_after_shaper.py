#!/usr/bin/python3
"""Golden PSD after a shaper, for advise::power_after_shaper (tests/advise/test_after_shaper.cpp).

The PSD a shaper leaves is P(f)·V(f)², V the shaper's residual vibration (the ratio of residual to
unshaped amplitude, thesis Eq. 2.19 after Singer & Seering 1990 / Magee & Book 1992), taken worst
over test damping ratios and frequency scales s (V at s·f). Computed here with NumPy alone from the
closed-form ZV and ZVD shapers (Singer & Seering 1990: K = exp(-ζπ/√(1-ζ²)), impulses at multiples
of half the damped period, amplitudes 1, K / (1+K) and 1, 2K, K² / (1+K)²), on a seeded spectrum:
two Lorentzian lines (20 Hz, 31 Hz) times χ²(14)/14 scatter (Welch's average of seven segments).

Run with Debian's Python (NumPy):  /usr/bin/python3 tests/golden/gen_after_shaper.py
Writes tests/golden/after_shaper_reference.json.
"""
import json
import os

import numpy as np

CASES = [  # (shaper, design frequency Hz, design ζ, test ζ, frequency scales)
    ("zv", 20.0, 0.05, [0.05], [1.0]),
    ("zvd", 20.0, 0.05, [0.03, 0.05, 0.08], [0.95, 1.0, 1.05]),
    ("zv", 24.5, 0.12, [0.075, 0.1, 0.15], [1.0]),
]


def impulses(name, f_hz, zeta):
    wd = 2 * np.pi * f_hz * np.sqrt(1 - zeta**2)
    k = np.exp(-zeta * np.pi / np.sqrt(1 - zeta**2))
    half = np.pi / wd
    if name == "zv":
        a = np.array([1.0, k]) / (1 + k)
    else:
        a = np.array([1.0, 2 * k, k * k]) / (1 + k) ** 2
    return np.arange(len(a)) * half, a


def residual(t, a, f_hz, zeta):
    """V(ω, ζ): |Σ A_i e^{-ζω(t_N - t_i)} e^{jω_d t_i}| / ΣA_i, for every frequency in f_hz."""
    w = 2 * np.pi * np.asarray(f_hz)[:, None]
    wd = w * np.sqrt(1 - zeta**2)
    terms = a * np.exp(-zeta * w * (t[-1] - t)) * np.exp(1j * wd * t)
    return np.abs(terms.sum(axis=1)) / a.sum()


def spectrum(rng):
    f = np.arange(0, 801) * 0.1
    line = lambda f0, z, p: p / (1 + ((f - f0) / (z * f0)) ** 2)
    clean = line(20.0, 0.05, 1.0) + line(31.0, 0.04, 0.3) + 1e-3
    return f, clean * rng.chisquare(14, f.size) / 14


def main():
    rng = np.random.default_rng(20)
    f, p = spectrum(rng)
    cases = []
    for name, f0, zeta, dampings, scales in CASES:
        t, a = impulses(name, f0, zeta)
        v = np.zeros_like(f)
        for z in dampings:
            for s in scales:
                v = np.maximum(v, residual(t, a, s * f, z))
        cases.append({"shaper": name, "design_frequency_hz": f0, "design_damping": zeta,
                      "test_damping_ratios": dampings, "frequency_scales": scales,
                      "impulse_times_s": t.tolist(), "impulse_amplitudes": a.tolist(),
                      "after_shaper": (p * v**2).tolist()})
    doc = {"generator": "tests/golden/gen_after_shaper.py", "seed": 20,
           "frequency_hz": f.tolist(), "power": p.tolist(), "cases": cases}
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "after_shaper_reference.json")
    with open(out, "w", encoding="utf-8") as fh:
        json.dump(doc, fh, indent=1)
        fh.write("\n")


if __name__ == "__main__":
    main()
