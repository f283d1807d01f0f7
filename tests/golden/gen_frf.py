#!/usr/bin/python3
"""Golden data for clearshape's frequency-response estimate (dsp/frf.hpp), computed with SciPy.

Run with Debian's Python (it has SciPy):   /usr/bin/python3 tests/golden/gen_frf.py
Writes tests/golden/dsp_frf.json (committed; CI never regenerates it). The input is seeded white
noise, the output that noise through a known IIR filter (a lightly damped 2nd-order resonance,
discretised by the bilinear transform) plus seeded measurement noise; both are stored beside the
expected spectra so the C++ test reads everything from the same file.
"""
import json
import os

import numpy as np
import scipy
from scipy import signal

HERE = os.path.dirname(os.path.abspath(__file__))


def cplx(values):
    return [[float(np.real(v)), float(np.imag(v))] for v in values]


def main():
    fs = 1000.0
    n = 6000
    rng = np.random.default_rng(20261126)
    x = rng.standard_normal(n)
    # A 2nd-order resonance at 40 Hz, zeta 0.05, DC gain 2 (bilinear transform, prewarped).
    wn = 2 * np.pi * 40.0
    b, a = signal.bilinear([2.0 * wn**2], [1.0, 2 * 0.05 * wn, wn**2], fs=fs)
    y = signal.lfilter(b, a, x) + 0.2 * rng.standard_normal(n)
    settings = [
        dict(window="hann", nperseg=256),  # scipy's defaults: noverlap 128, constant detrend
        dict(window="hamming", nperseg=500, noverlap=250),
        dict(window="hann", nperseg=600, noverlap=450, nfft=1024, detrend="linear"),
        dict(window="boxcar", nperseg=333, noverlap=0, detrend=False),
        dict(window="hann", nperseg=1333, noverlap=666),  # MATLAB's default: 8 segments, floor(n/4.5)
    ]
    cases = []
    for s in settings:
        f, pxy = signal.csd(x, y, fs=fs, **s)
        _, pxx = signal.welch(x, fs=fs, **s)
        _, pyy = signal.welch(y, fs=fs, **s)
        _, cxy = signal.coherence(x, y, fs=fs, **s)
        entry = {k: (v if v is not False else "none") for k, v in s.items()}
        entry.update({"frequency_hz": f.tolist(), "pxy": cplx(pxy), "pxx": pxx.tolist(), "pyy": pyy.tolist(),
                      "h1": cplx(pxy / pxx), "coherence": cxy.tolist()})
        cases.append(entry)
    payload = {"generator": "tests/golden/gen_frf.py", "scipy": scipy.__version__, "numpy": np.__version__,
               "fs_hz": fs, "filter_b": b.tolist(), "filter_a": a.tolist(), "x": x.tolist(), "y": y.tolist(),
               "cases": cases}
    path = os.path.join(HERE, "dsp_frf.json")
    with open(path, "w") as out:
        json.dump(payload, out, separators=(",", ":"))  # floats written with repr: round-trip exact
        out.write("\n")
    print(f"wrote {path} ({os.path.getsize(path)} bytes)")


if __name__ == "__main__":
    main()
