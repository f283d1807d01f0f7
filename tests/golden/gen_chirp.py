#!/usr/bin/python3
"""Golden data for the `chirp` signal (signal::Chirp), computed with scipy.signal.chirp.

Run with Debian's Python (it has SciPy):   /usr/bin/python3 tests/golden/gen_chirp.py
Writes tests/golden/signal_chirp.csv: time_s and one column per sweep, sampled at 1 kHz over
5 s, for amplitude 1.5, offset 0.25, phase 30 deg, start 0.5 s, f0 0.5 Hz -> f1 20 Hz in 4 s.
signal::Chirp is offset + amplitude*sin(theta + phase) = scipy's cos form with phi = phase - 90,
for 0 <= t - start <= sweep_s, and the offset outside. The committed file records the versions.
"""
import os

import numpy as np
import scipy
from scipy import signal

HERE = os.path.dirname(os.path.abspath(__file__))

AMPLITUDE, OFFSET, PHASE_DEG, START_S = 1.5, 0.25, 30.0, 0.5
F0_HZ, F1_HZ, SWEEP_S = 0.5, 20.0, 4.0
RATE_HZ, DURATION_S = 1000.0, 5.0


def chirp(t, method):
    tau = t - START_S
    inside = (tau >= 0.0) & (tau <= SWEEP_S)
    y = np.full_like(t, OFFSET)
    y[inside] = OFFSET + AMPLITUDE * signal.chirp(tau[inside], F0_HZ, SWEEP_S, F1_HZ, method=method,
                                                  phi=PHASE_DEG - 90.0)
    return y


def main():
    n = int(np.floor(DURATION_S * RATE_HZ)) + 1
    t = np.arange(n) / RATE_HZ
    cols = {"linear": chirp(t, "linear"), "logarithmic": chirp(t, "logarithmic")}
    path = os.path.join(HERE, "signal_chirp.csv")
    with open(path, "w") as f:
        f.write(f"# scipy {scipy.__version__}, numpy {np.__version__}: scipy.signal.chirp\n")
        f.write("time_s,linear,logarithmic\n")
        for i in range(n):
            f.write(f"{t[i]!r},{cols['linear'][i]!r},{cols['logarithmic'][i]!r}\n")
    print("wrote", path)


if __name__ == "__main__":
    main()
