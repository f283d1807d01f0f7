#!/usr/bin/python3
"""Golden data for the jerk-limited point-to-point move (tests/signal/test_jerk_limited.cpp).

Run with Debian's Python:  /usr/bin/python3 tests/golden/gen_jerk_limited.py
Writes, next to this script:
  signal_jerk_limited.csv  distance, v_max, a_max, j_max, duration_s, peak_velocity,
                           peak_acceleration, then the position at 0, T/10, …, T (p0 … p10)

Independent of the C++ code (which follows Biagiotti & Melchiorri's case analysis of the
segment times Tj, Ta, Tv): here the rest-to-rest minimum-time move is parametrised by its peak
velocity vp. Accelerating from rest to vp under the limits takes
    t_acc(vp) = vp/a + a/j  if vp >= a²/j  (a trapezoidal acceleration reaches a)
              = 2 sqrt(vp/j) otherwise     (a triangular one)
and covers d_acc = vp·t_acc/2 (the acceleration pulse is symmetric). The fastest move uses the
largest vp <= v_max with 2·d_acc(vp) <= D (found with scipy.optimize.brentq where v_max is not
reached) and cruises for (D − 2 d_acc)/vp:  T = 2 t_acc(vp) + (D − 2 d_acc(vp))/vp.
The profile is then rebuilt as a piecewise-constant jerk and integrated three times with
scipy.interpolate.PPoly; the script asserts that it ends at D at rest and never exceeds a limit
before anything is written.
"""
import os

import numpy as np
from scipy.interpolate import PPoly
from scipy.optimize import brentq

HERE = os.path.dirname(os.path.abspath(__file__))

# (distance, v_max, a_max, j_max): every branch — v and a reached, v reached with a triangular
# acceleration, a reached without cruise, neither — in rad, deg and mm scales.
CASES = [
    (1.0, 1.0, 2.0, 10.0),      # v, a reached
    (1.0, 1.0, 4.0, 10.0),      # v reached, a not (v·j < a²)
    (1.0, 5.0, 2.0, 10.0),      # a reached, no cruise
    (0.05, 5.0, 2.0, 10.0),     # neither
    (0.4, 1.0, 2.0, 10.0),      # a reached, no cruise (short)
    (2.0, 3.0, 20.0, 500.0),    # joint-like (rad)
    (0.3, 3.0, 20.0, 500.0),
    (0.01, 3.0, 20.0, 500.0),
    (90.0, 180.0, 900.0, 9000.0),   # degrees
    (250.0, 500.0, 5000.0, 1e5),    # mm
    (1e-4, 1.0, 1.0, 1.0),
    (1.0, 0.5, 100.0, 1e4),     # velocity-limited, almost a trapezoid
]


def t_acc(vp, a, j):
    return vp / a + a / j if vp >= a * a / j else 2.0 * np.sqrt(vp / j)


def move(distance, v, a, j):
    """Peak velocity, duration and the jerk breakpoints of the minimum-time move."""
    reach = lambda vp: vp * t_acc(vp, a, j) - distance  # 2·d_acc(vp) − D
    vp = v if reach(v) <= 0.0 else brentq(reach, 0.0, v, xtol=1e-300, rtol=4 * np.finfo(float).eps)
    ta = t_acc(vp, a, j)
    cruise = (distance - vp * ta) / vp
    tj = min(a / j, np.sqrt(vp / j))
    flat = ta - 2 * tj
    durations = [tj, flat, tj, cruise, tj, flat, tj]
    jerks = [j, 0, -j, 0, -j, 0, j]
    return vp, j * tj, 2 * ta + cruise, durations, jerks


def integrate(durations, jerks):
    """Position PPoly of a piecewise-constant jerk starting at rest."""
    keep = [k for k, d in enumerate(durations) if d > 0]
    x = np.concatenate([[0.0], np.cumsum([durations[k] for k in keep])])
    jerk = PPoly(np.array([[jerks[k] for k in keep]], dtype=float), x)
    return jerk.antiderivative(3)


def main():
    rows = []
    for distance, v, a, j in CASES:
        vp, ap, duration, durations, jerks = move(distance, v, a, j)
        position = integrate(durations, jerks)
        t = np.linspace(0.0, duration, 20001)
        vel, acc = position.derivative(1)(t), position.derivative(2)(t)
        assert abs(position(duration) - distance) < 1e-12 * max(1.0, distance)
        assert abs(vel[-1]) < 1e-9 * v and abs(acc[-1]) < 1e-9 * a
        assert vel.max() <= v * (1 + 1e-12) and np.abs(acc).max() <= a * (1 + 1e-12)
        assert abs(vel.max() - vp) < 1e-6 * vp
        samples = position(np.linspace(0.0, duration, 11))
        rows.append([distance, v, a, j, duration, vp, ap, *samples])
    names = "distance,v_max,a_max,j_max,duration_s,peak_velocity,peak_acceleration," + ",".join(
        f"p{k}" for k in range(11))
    np.savetxt(os.path.join(HERE, "signal_jerk_limited.csv"), np.array(rows), delimiter=",", fmt="%.17g",
               header=names, comments="")


if __name__ == "__main__":
    main()
