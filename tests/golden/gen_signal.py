#!/usr/bin/python3
"""Golden data for clearshape's `signal` module, from an independent NumPy/SciPy implementation.

Run with Debian's Python (it has SciPy):  /usr/bin/python3 tests/golden/gen_signal.py
Writes tests/golden/signal_*.csv (committed; CI never regenerates them). The C++ tests in
tests/signal/test_golden.cpp rebuild the same cases and compare with the tolerances stated there.

Independent parts:
  * PRBS bits: scipy.signal.max_len_seq. Its convention: state[j] is output bit j, each step
    outputs state[0] and feeds back state[0] XOR state[t] for t in taps, i.e. the recurrence
    a[k+n] = a[k] ^ XOR_t a[k+t] with p(x) = x^n + sum x^t + 1. clearshape's Lfsr uses the same
    recurrence with seed bit j = a[j], so state = [(seed >> j) & 1 for j in range(n)] and
    taps = clearshape's prbs_taps(n). We also check here that every tap set up to n = 20 gives
    period exactly 2^n - 1.
  * Jerk-limited S-curve: integrated three times from its piecewise-constant jerk with
    scipy.interpolate.PPoly.antiderivative (the C++ uses the closed-form cubic pieces).
  * Step/ramp/trapezoid/staircase/parabola/sine: vectorised NumPy from the definitions.
  * Position-mode path (30 Hz held velocity, whole counts, 500 kHz cap): written from the spec
    in include/clearshape/signal/position_path.hpp with np.interp for the trajectory.
  * Speed-mode path: 12-bit +/-10 V D/A by clipping and rounding to the LSB grid.
Switching instants use the same 1 ns tolerance as the C++ (t >= start - 1e-9).
"""
import os

import numpy as np
from scipy.interpolate import PPoly
from scipy.signal import max_len_seq

HERE = os.path.dirname(os.path.abspath(__file__))
TOL = 1e-9

# clearshape's primitive taps (src/signal/prbs.cpp; Alfke, Xilinx XAPP 052, order 2: x^2+x+1)
TAPS = {2: [1], 3: [2], 4: [3], 5: [3], 6: [5], 7: [6], 8: [6, 5, 4], 9: [5], 10: [7],
        11: [9], 12: [6, 4, 1], 13: [4, 3, 1], 14: [5, 3, 1], 15: [14], 16: [15, 13, 4],
        17: [14], 18: [11], 19: [6, 2, 1], 20: [17], 21: [19], 22: [21], 23: [18],
        24: [23, 22, 17], 25: [22], 26: [6, 2, 1], 27: [5, 2, 1], 28: [25], 29: [27],
        30: [6, 4, 1], 31: [28]}


def write_csv(name, header, columns):
    data = np.column_stack(columns)
    path = os.path.join(HERE, name)
    np.savetxt(path, data, delimiter=",", header=",".join(header), comments="", fmt="%.17g")
    print(f"wrote {path}: {data.shape[0]} rows, {os.path.getsize(path)} bytes")


def reached(t, start):
    return t >= start - TOL


# ---- rise shapes --------------------------------------------------------------------------

_JERK = PPoly(np.array([[32.0, -32.0, -32.0, 32.0]]), np.array([0.0, 0.25, 0.5, 0.75, 1.0]))
_SCURVE = _JERK.antiderivative(3)
assert abs(_SCURVE(1.0) - 1.0) < 1e-14 and abs(_SCURVE.derivative(1)(1.0)) < 1e-14


def rise(shape, u):
    u = np.clip(u, 0.0, 1.0)
    return u if shape == "linear" else _SCURVE(u)


def transition(shape, rise_s, start_s, t):
    on = reached(t, start_s)
    if rise_s <= 0:
        return on.astype(float)
    return np.where(on, rise(shape, np.maximum(0.0, t - start_s) / rise_s), 0.0)


# ---- signals ------------------------------------------------------------------------------

def step(t, amplitude, start_s, rise_s=0.0, shape="linear"):
    return amplitude * transition(shape, rise_s, start_s, t)


def ramp(t, slope, start_s, limit):
    v = np.where(reached(t, start_s), slope * np.maximum(0.0, t - start_s), 0.0)
    return np.minimum(v, limit) if slope > 0 else np.maximum(v, limit)


def sine(t, amplitude, frequency_hz, phase_rad, offset, start_s):
    return np.where(reached(t, start_s),
                    offset + amplitude * np.sin(2 * np.pi * frequency_hz * (t - start_s) + phase_rad),
                    offset)


def stacked(t, levels, dwell_s, start_s, rise_s, shape, repeat):
    levels = np.asarray(levels, float)
    m = len(levels)
    k = np.maximum(0.0, np.floor((t - start_s + TOL) / dwell_s)).astype(int)

    def level(j):
        out = np.zeros_like(t)
        ok = j >= 0
        out[ok] = levels[j[ok] % m] if repeat else levels[np.minimum(j[ok], m - 1)]
        return out

    to, frm = level(k), level(k - 1)
    if rise_s > 0:
        v = frm + (to - frm) * rise(shape, np.maximum(0.0, t - (start_s + k * dwell_s)) / rise_s)
    else:
        v = to
    return np.where(reached(t, start_s), v, 0.0)


def trapezoid(t, amplitude, start_s, rise_s, hold_s, fall_s, shape):
    return amplitude * (transition(shape, rise_s, start_s, t)
                        - transition(shape, fall_s, start_s + rise_s + hold_s, t))


def prbs_bits(order, seed, count):
    state = [(seed >> j) & 1 for j in range(order)]
    return max_len_seq(order, state=state, length=count, taps=TAPS[order])[0]


def prbs(t, order, bit_period_s, amplitude, offset, seed, start_s):
    k = np.maximum(0, np.floor((t - start_s + TOL) / bit_period_s)).astype(np.int64)
    period = 2 ** order - 1
    bits = prbs_bits(order, seed, period)[k % period]
    return np.where(reached(t, start_s), offset + amplitude * (2.0 * bits - 1.0), offset)


# ---- drive command paths ------------------------------------------------------------------

def position_path(t, p_deg, update_hz, counts_per_rev, gear, fmax_hz, mode):
    p = p_deg * np.pi / 180.0
    period = 1.0 / update_hz
    h = t[1] - t[0]  # = 1/rate exactly, the C++ sample_time_s
    cpr = counts_per_rev / (gear * 2 * np.pi)
    nmax = int(np.floor(fmax_hz / update_hz + 1e-9))
    updates = int(np.floor((t[-1] - t[0] + TOL) / period)) + 1
    which = np.floor((t - t[0] + TOL) / period).astype(int)
    count = int(np.floor(p[0] * cpr + 0.5))
    aimed = p[0]
    commanded = np.empty_like(t)
    freq = np.empty_like(t)
    saturated = 0
    for k in range(updates):
        tk = t[0] + k * period
        if mode == "lookahead":
            aimed = np.interp(tk + period, t, p)
        else:
            aimed += (np.interp(tk, t, p) - np.interp(tk - h, t, p)) / h * period
        want = int(np.floor(aimed * cpr + 0.5)) - count
        n = int(np.clip(want, -nmax, nmax))
        saturated += n != want
        idx = which == k
        frac = np.clip(np.maximum(0.0, t[idx] - tk) * update_hz, 0.0, 1.0)
        done = np.minimum(abs(n), np.floor(abs(n) * frac + 1e-9))
        commanded[idx] = (count + np.sign(n) * done) / cpr
        freq[idx] = n * update_hz
        count += n
    return commanded * 180.0 / np.pi, freq, saturated


def daq(command, volts_per_unit, bits=12, full_scale=10.0):
    v = command * volts_per_unit
    clipped = np.abs(v) > full_scale
    lsb = 2 * full_scale / 2 ** bits
    code = np.clip(np.floor(np.clip(v, -full_scale, full_scale) / lsb + 0.5),
                   -2 ** (bits - 1), 2 ** (bits - 1) - 1)
    return code * lsb, int(clipped.sum())


def times(rate_hz, duration_s):
    n = int(np.floor(duration_s * rate_hz + 1e-9)) + 1  # sample_count() of clearshape
    return np.arange(n) * (1.0 / rate_hz)


def main():
    # -- PRBS: every tap set is maximal (n <= 20 here; n <= 31 algebraically in C++) ---------
    for n in range(2, 21):
        seq = prbs_bits(n, 1, 2 ** n - 1)
        assert seq.sum() == 2 ** (n - 1), n
        # period exactly 2^n - 1: no shorter cyclic shift of the sequence equals itself
        ext = np.concatenate([seq, seq[: n + 1]])
        windows = np.lib.stride_tricks.sliding_window_view(ext, n)[: 2 ** n - 1]
        codes = windows @ (1 << np.arange(n, dtype=np.int64))
        assert len(np.unique(codes)) == 2 ** n - 1, n  # every non-zero state once per period

    rows = []
    cases = [(n, 1, 2 ** n - 1) for n in range(2, 13)]
    cases += [(n, (0x5A5A5A5A & (2 ** n - 1)) or 1, 1023) for n in range(13, 32)]
    cases += [(7, 0x55, 127), (10, 777, 1023)]
    for n, seed, count in cases:
        bits = prbs_bits(n, seed, count)
        rows.append(np.column_stack([np.full(count, n), np.full(count, seed), np.arange(count), bits]))
    rows = np.vstack(rows)
    write_csv("signal_prbs_bits.csv", ["order", "seed", "index", "bit"], rows.T)

    # -- command signals, 500 Hz over 3 s --------------------------------------------------
    t = times(500.0, 3.0)
    write_csv("signal_shapes.csv",
              ["time_s", "step_ideal", "step_linear", "step_scurve", "ramp_limited", "sine",
               "double_step", "stacked_steps", "parabolic", "trapezoid_linear",
               "trapezoid_scurve", "pulse", "prbs"],
              [t,
               step(t, 2.5, 0.3),
               step(t, 10.0, 0.25, 0.4, "linear"),
               step(t, -7.0, 0.5, 0.6, "s-curve"),
               ramp(t, 4.0, 0.2, 5.0),
               sine(t, 3.0, 1.7, 0.4, 1.0, 0.1),
               step(t, 8.0, 0.2, 0.3, "s-curve") + step(t, -3.0, 1.3, 0.3, "s-curve"),
               stacked(t, [1.0, 3.0, -2.0], 0.7, 0.1, 0.2, "linear", True),
               np.where(reached(t, 0.4), 0.5 * 6.0 * np.maximum(0.0, t - 0.4) ** 2, 0.0),
               trapezoid(t, 5.0, 0.2, 0.3, 0.8, 0.5, "linear"),
               trapezoid(t, -4.0, 0.5, 0.4, 0.3, 0.6, "s-curve"),
               trapezoid(t, 2.0, 1.0, 0.0, 0.5, 0.0, "linear"),
               prbs(t, 5, 0.05, 2.0, 1.0, 7, 0.12)])

    # -- position-mode path ------------------------------------------------------------------
    def path_case(name, t, p_deg, update_hz=30.0, cpr=3000.0, gear=1.0, fmax=500e3, mode="lookahead"):
        commanded, freq, saturated = position_path(t, p_deg, update_hz, cpr, gear, fmax, mode)
        write_csv(name, ["time_s", "command_deg", "commanded_deg", "pulse_frequency_hz"],
                  [t, p_deg, commanded, freq])
        print(f"  {name}: saturated updates = {saturated}")

    t = times(1000.0, 1.0)
    path_case("signal_path_step.csv", t, step(t, 10.0, 0.1))
    t = times(1000.0, 1.5)
    path_case("signal_path_scurve.csv", t, step(t, 56.0, 0.2, 0.5, "s-curve"))
    t = times(1000.0, 1.2)
    path_case("signal_path_sampled.csv", t,
              step(t, 8.0, 0.1, 0.1, "linear") + step(t, 8.0, 0.6, 0.1, "linear"), mode="sampled")
    t = times(1000.0, 0.5)
    path_case("signal_path_saturated.csv", t, step(t, 90.0, 0.05), gear=0.02)
    t = times(800.0, 1.5)
    path_case("signal_path_reverse.csv", t, trapezoid(t, 20.0, 0.1, 0.2, 0.2, 0.3, "linear"),
              update_hz=25.0, cpr=2500.0, gear=2.0)

    # -- speed-mode path ----------------------------------------------------------------------
    t = times(1000.0, 1.0)
    command = sine(t, 1500.0, 2.0, 0.0, 0.0, 0.0)  # deg/s; 0.008 V per deg/s -> +/-12 V
    volts, clipped = daq(command, 0.008)
    write_csv("signal_daq.csv", ["time_s", "command_deg_s", "daq_v"], [t, command, volts])
    print(f"  signal_daq.csv: clipped samples = {clipped}")


if __name__ == "__main__":
    main()
