#!/usr/bin/python3
"""Golden data for shaping/apply (offline shaping and discretisation of impulse shapers).

Run with Debian's Python:  /usr/bin/python3 tests/golden/gen_apply.py
Writes, next to this script:
  apply_input.csv              time_s, step, ramp, prbs, sine (the sampled inputs)
  apply_<shaper>_impulses.csv  time_s, amplitude (the continuous shaper, ΣA = 1)
  apply_<shaper>.csv           time_s, step, ramp, prbs, sine (shaped, extended by the duration)
  apply_exact_taps.csv         shaper, delay_samples, weight (Murphy–Watanabe split, solved here
                               as a 2×2 linear system per impulse with numpy.linalg.solve)

Independent of the C++ code: the shaped output is y(t_k) = Σ Aᵢ·u(t_k − tᵢ) with u linear
between samples and held beyond its ends (numpy.interp), cross-checked against Vaughan's
digseq idea (each impulse split linearly over the two neighbouring samples into a dense
sequence) convolved with numpy.convolve. Impulse times deliberately fall between samples.
"""
import os

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
TS = 1e-3            # sample time [s]
N = 400              # input samples
START_S = 0.25       # first sample time [s]
F_HZ = 13.7          # design natural frequency (off the 1 ms grid on purpose)
ZETA = 0.07


def zv_family(n_derivatives, f_hz, zeta):
    """Singer & Seering 1990: C(n+1,k)·K^k/(1+K)^(n+1) at k·Td/2."""
    k = np.exp(-zeta * np.pi / np.sqrt(1 - zeta**2))
    td = 1.0 / (f_hz * np.sqrt(1 - zeta**2))
    n = n_derivatives + 1
    from math import comb
    a = np.array([comb(n, i) * k**i for i in range(n + 1)])
    return np.arange(n + 1) * td / 2, a / a.sum()


def ei_fit(f_hz, zeta, v=0.05):
    """Singhose's damped EI curve fit (as in Klipper's shaper_defs.py / Vaughan), Td-scaled."""
    td = 1.0 / (f_hz * np.sqrt(1 - zeta**2))
    a1 = 0.24968 + 0.24961 * v + (0.80008 + 1.23328 * v) * zeta + (0.49599 + 3.17316 * v) * zeta**2
    a3 = 0.25149 + 0.21474 * v + (-0.83249 + 1.41498 * v) * zeta + (0.85181 - 4.90094 * v) * zeta**2
    a2 = 1 - a1 - a3
    t2 = (0.4999 + (0.46159 * v + 8.57843 * v**2) * zeta + (4.26169 * v - 108.644 * v**2) * zeta**2
          + (1.75601 * v + 336.989 * v**2) * zeta**3) * td
    a = np.array([a1, a2, a3])
    return np.array([0.0, t2, td]), a / a.sum()


def signals():
    k = np.arange(N)
    t = START_S + k * TS
    step = (k >= 50).astype(float)
    ramp = np.clip((k - 100) * TS * 2.5, 0.0, None)  # 2.5 units/s from sample 100
    rng = np.random.default_rng(20150601)
    prbs = np.empty(N)
    i = 0
    level = 0.0
    while i < N:                                     # random levels held 5..40 samples
        hold = int(rng.integers(5, 41))
        prbs[i:i + hold] = level
        level = float(rng.normal(0.0, 1.0))
        i += hold
    sine = 0.3 + np.sin(2 * np.pi * 3.1 * (t - START_S) + 0.4)  # non-zero first value
    return t, {"step": step, "ramp": ramp, "prbs": prbs, "sine": sine}


def shape_interp(u, times, amps, length):
    """y[k] = Σ Aᵢ·u(k·Ts − tᵢ), u piecewise linear, held at both ends (np.interp)."""
    grid = np.arange(N) * TS
    tk = np.arange(length) * TS
    return sum(a * np.interp(tk - ti, grid, u) for ti, a in zip(times, amps))


def digseq(times, amps):
    """Dense digitised sequence: impulse A at (m+f)·Ts → A(1−f) at m, A·f at m+1."""
    x = times / TS
    m = np.floor(x).astype(int)
    f = x - m
    seq = np.zeros(m.max() + 2)
    for mi, fi, a in zip(m, f, amps):
        seq[mi] += a * (1 - fi)
        seq[mi + 1] += a * fi
    return np.trim_zeros(seq, "b")


def shape_convolve(u, seq):
    d = len(seq) - 1
    padded = np.concatenate([np.full(d, u[0]), u, np.full(d, u[-1])])
    return np.convolve(padded, seq, mode="valid")


def exact_split(times, amps, f_hz, zeta):
    """Murphy & Watanabe 1992: on-grid B_m, B_m+1 with the impulse's complex vibration at the
    mode reproduced: B_m·e^{−p·m·Ts} + B_m+1·e^{−p·(m+1)·Ts} = A·e^{−p·t}, p = −ζωn + jωd.
    Solved numerically (real and imaginary parts), then rescaled to ΣB = ΣA."""
    wn = 2 * np.pi * f_hz
    p = complex(-zeta * wn, wn * np.sqrt(1 - zeta**2))
    taps = {}
    for ti, a in zip(times, amps):
        m = int(np.floor(ti / TS))
        z0, z1, rhs = np.exp(-p * m * TS), np.exp(-p * (m + 1) * TS), a * np.exp(-p * ti)
        mat = np.array([[z0.real, z1.real], [z0.imag, z1.imag]])
        b = np.linalg.solve(mat, np.array([rhs.real, rhs.imag]))
        taps[m] = taps.get(m, 0.0) + b[0]
        taps[m + 1] = taps.get(m + 1, 0.0) + b[1]
    taps = {d: w for d, w in taps.items() if abs(w) > 1e-14}  # an on-grid impulse has B_m+1 = 0
    delays = np.array(sorted(taps))
    weights = np.array([taps[d] for d in delays])
    return delays, weights * amps.sum() / weights.sum()


def write_csv(name, header, columns):
    path = os.path.join(HERE, name)
    with open(path, "w") as fh:
        fh.write(",".join(header) + "\n")
        for row in zip(*columns):
            fh.write(",".join(repr(float(v)) for v in row) + "\n")


def main():
    t, sig = signals()
    names = list(sig)
    write_csv("apply_input.csv", ["time_s"] + names, [t] + [sig[n] for n in names])
    shapers = {
        "zv": zv_family(0, F_HZ, ZETA),
        "zvd": zv_family(1, F_HZ, ZETA),
        "zvdd": zv_family(2, F_HZ, ZETA),
        "ei": ei_fit(F_HZ, ZETA),
    }
    exact_rows = ([], [], [])
    for sname, (times, amps) in shapers.items():
        off_grid = np.abs(times[1:] / TS - np.round(times[1:] / TS))
        assert off_grid.min() > 0.05, "impulse times must fall between samples"
        write_csv(f"apply_{sname}_impulses.csv", ["time_s", "amplitude"], [times, amps])
        seq = digseq(times, amps)
        length = N + int(np.ceil(times[-1] / TS))
        assert len(seq) - 1 == length - N
        outs = []
        for n in names:
            y_interp = shape_interp(sig[n], times, amps, length)
            y_conv = shape_convolve(sig[n], seq)
            assert np.max(np.abs(y_interp - y_conv)) < 1e-13, (sname, n)
            outs.append(y_interp)
        write_csv(f"apply_{sname}.csv", ["time_s"] + names,
                  [START_S + np.arange(length) * TS] + outs)
        delays, weights = exact_split(times, amps, F_HZ, ZETA)
        exact_rows[0].extend([list(shapers).index(sname)] * len(delays))
        exact_rows[1].extend(delays)
        exact_rows[2].extend(weights)
    write_csv("apply_exact_taps.csv", ["shaper_index", "delay_samples", "weight"], exact_rows)
    print("shapers (index order):", ", ".join(shapers))


if __name__ == "__main__":
    main()
