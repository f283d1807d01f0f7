#!/usr/bin/python3
"""Golden data for the worn-coupling rig (issue 19; run with /usr/bin/python3, SciPy is the
independent reference). Writes tests/golden/worn_coupling_link.csv.

The model, written here from its physics and not from clearshape's code:
  drive    thesis Eq. 4.2 position model G(s) = Kp (1 + Tz s) / ((1 + 2 Zeta Tw s + (Tw s)^2)(1 + Tp3 s)),
           Kp 0.9959, Tz 0.0042, Zeta 0.9968, Tw 0.0102, Tp3 0.0034: command (deg) -> motor angle (deg)
  command  zero-order hold at 1 kHz: 0 until 0.1 s, a ramp to 20 deg over 0.0333 s, held
  link     a dead zone: relative angle phi = theta_link - theta_motor turns freely for |phi| <= beta,
           beta = 0.5 deg (1 deg total play); beyond it the calibrated linear flank of thesis Eq. 4.3,
           F = max(0, K delta + D delta_dot), delta = |phi| - beta, K 45.158834415041305 N m/rad,
           D 0.12355192243621643 N m s/rad, acting against phi
  friction bearing torque on the relative rate: -c tanh(phi_dot / v_t) - b phi_dot,
           c 0.01 N m, v_t 1e-3 rad/s, b 1e-3 N m s/rad; air drag -b_g omega, b_g 1e-4 N m s/rad
  inertia  J = 5e-3 kg m^2
integrated by scipy.integrate.solve_ivp (DOP853, rtol 1e-11, atol 1e-14) one input sample at a
time (the input is constant within it); its error control shrinks the step onto each contact onset
and separation, where the dashpot force jumps. From rest at phi(0) = f beta for f = -1, 0, 1. Column link_deg_f<f> is the link angle theta_m + phi,
relative to its value at t = 0, in degrees.
"""
import os

import numpy as np
from scipy import integrate, signal

KP, TZ, ZETA, TW, TP3 = 0.9959, 0.0042, 0.9968, 0.0102, 0.0034
K, D = 45.158834415041305, 0.12355192243621643
C, VT, B, BG, J = 0.01, 1e-3, 1e-3, 1e-4, 5e-3
BETA = np.deg2rad(0.5)
TS, DURATION = 1e-3, 1.5


def command(k):
    t = k * TS
    if t <= 0.1:
        return 0.0
    return 20.0 * min(1.0, (t - 0.1) / 0.0333)


def drive():
    num = [KP * TZ, KP]
    den = np.polymul([TW * TW, 2.0 * ZETA * TW, 1.0], [TP3, 1.0])
    a, b, c, d = signal.tf2ss(num, den)
    return a, b[:, 0], c[0], d[0, 0]


A, Bv, Cv, Dv = drive()
ND = A.shape[0]


def motor(x, u):  # angle and rate in rad, rad/s
    xd = A @ x + Bv * u
    return np.deg2rad(Cv @ x + Dv * u), np.deg2rad(Cv @ xd)


def flank_force(phi, phi_dot):
    s = 1.0 if phi >= 0 else -1.0
    delta = s * phi - BETA
    if delta <= 0:
        return 0.0, s
    return max(0.0, K * delta + D * s * phi_dot), s


def rhs(_t, y, u):
    x, phi, w = y[:ND], y[ND], y[ND + 1]
    _, wm = motor(x, u)
    phi_dot = w - wm
    f, s = flank_force(phi, phi_dot)
    tau = -s * f - C * np.tanh(phi_dot / VT) - B * phi_dot - BG * w
    return np.concatenate([A @ x + Bv * u, [phi_dot, tau / J]])


def run(fraction):
    y = np.zeros(ND + 2)
    y[ND] = fraction * BETA
    n = int(round(DURATION / TS)) + 1
    out = np.empty(n)
    theta0 = motor(y[:ND], 0.0)[0] + y[ND]
    out[0] = 0.0
    for k in range(1, n):
        u = command(k - 1)
        sol = integrate.solve_ivp(rhs, ((k - 1) * TS, k * TS), y, method="DOP853", rtol=1e-11, atol=1e-14,
                                  args=(u,))
        y = sol.y[:, -1]
        out[k] = np.rad2deg(motor(y[:ND], u)[0] + y[ND] - theta0)
    return out


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    fractions = [-1.0, 0.0, 1.0]
    cols = [run(f) for f in fractions]
    t = np.arange(len(cols[0])) * TS
    data = np.column_stack([t] + cols)
    np.savetxt(os.path.join(here, "worn_coupling_link.csv"), data, delimiter=",",
               header="time_s,link_deg_f-1,link_deg_f0,link_deg_f1", comments="", fmt="%.12g")


if __name__ == "__main__":
    main()
