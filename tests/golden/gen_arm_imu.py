#!/usr/bin/python3
"""Golden data for the arm's last-link IMU (tests/arm/test_imu.cpp).

Run with Debian's Python:  /usr/bin/python3 tests/golden/gen_arm_imu.py
Writes, next to this script:
  arm_imu.csv  arm (0 scara-2, 1 vertical-2), q1_rad, q2_rad, qd1_rad_s, qd2_rad_s,
               qdd1_rad_s2, qdd2_rad_s2, mount_x_m, mount_y_m, mount_z_m (in the tool link's
               frame), gyro_{x,y,z}_rad_s and accel_{x,y,z}_m_s2 in the tool link's frame

Independent of the C++ code (which runs the outward pass of the recursive Newton–Euler algorithm
on KDL's segments): the planar two-link closed form. Both joints turn about the same axis k
(z for scara-2, y for vertical-2), so the tool link's frame is R(q1 + q2) and
  ω = (q̇1 + q̇2) k                                             (in the tool frame, k is fixed by R)
  p = (0, 0, h) + R(q1) (L1, 0, 0) + R(q1 + q2) r,   r = (L2, 0, 0) + mount
  p̈ = R(q1) (q̈1 K + q̇1² K²) (L1, 0, 0) + R(q12) (q̈12 K + q̇12² K²) r     (K = [k]×)
  accel = R(q12)ᵀ (p̈ − g),   g = (0, 0, −9.80665)
(Ṙ = S(ω) R differentiated twice for a body-fixed vector; Spong, Hutchinson & Vidyasagar, Robot
Modeling and Control, 2006, §4.2). Cross-checked here before anything is written: ω against
R(t)ᵀ Ṙ(t) and p̈ against the second central difference of p(q(t)) along the path
q(t) = q + q̇ t + q̈ t²/2 (to 1e-6).
"""
import os

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
G = np.array([0.0, 0.0, -9.80665])
# (axis, shoulder height h, L1, L2) of the built-in URDFs (src/arm/builtin.cpp)
ARMS = [(np.array([0.0, 0.0, 1.0]), 0.2, 0.25, 0.20), (np.array([0.0, 1.0, 0.0]), 0.4, 0.30, 0.25)]
MOUNTS = [np.zeros(3), np.array([-0.03, 0.012, 0.02])]


def skew(k):
    return np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])


def rot(k, angle):
    kx = skew(k)  # Rodrigues: R = I + sin θ K + (1 − cos θ) K²
    return np.eye(3) + np.sin(angle) * kx + (1.0 - np.cos(angle)) * kx @ kx


def position(arm, mount, q):
    k, h, l1, l2 = arm
    r = np.array([l2, 0.0, 0.0]) + mount
    return np.array([0.0, 0.0, h]) + rot(k, q[0]) @ np.array([l1, 0.0, 0.0]) + rot(k, q[0] + q[1]) @ r


def closed_form(arm, mount, q, qd, qdd):
    k, h, l1, l2 = arm
    kx = skew(k)
    r = np.array([l2, 0.0, 0.0]) + mount
    q12, qd12, qdd12 = q[0] + q[1], qd[0] + qd[1], qdd[0] + qdd[1]
    acc = rot(k, q[0]) @ (qdd[0] * kx + qd[0] ** 2 * kx @ kx) @ np.array([l1, 0.0, 0.0])
    acc += rot(k, q12) @ (qdd12 * kx + qd12 ** 2 * kx @ kx) @ r
    return qd12 * k, rot(k, q12).T @ (acc - G)


def cross_check(arm, mount, q, qd, qdd, gyro, accel):
    k = arm[0]
    path = lambda t: q + qd * t + 0.5 * qdd * t * t
    dt = 1e-4
    p = [position(arm, mount, path(t)) for t in (-dt, 0.0, dt)]
    acc = (p[0] - 2.0 * p[1] + p[2]) / dt ** 2
    r0, r1, r2 = (rot(k, sum(path(t))) for t in (-dt, 0.0, dt))
    w = r1.T @ (r2 - r0) / (2.0 * dt)  # [ω]× in the body frame
    omega = np.array([w[2, 1], w[0, 2], w[1, 0]])
    assert np.allclose(omega, gyro, atol=1e-6), (omega, gyro)
    assert np.allclose(r1.T @ (acc - G), accel, atol=1e-5), (r1.T @ (acc - G), accel)


def main():
    rng = np.random.default_rng(24)
    rows = []
    for index, arm in enumerate(ARMS):
        for mount in MOUNTS:
            for _ in range(12):
                q = rng.uniform(-2.5, 2.5, 2)
                qd = rng.uniform(-6.0, 6.0, 2)
                qdd = rng.uniform(-80.0, 80.0, 2)
                gyro, accel = closed_form(arm, mount, q, qd, qdd)
                cross_check(arm, mount, q, qd, qdd, gyro, accel)
                rows.append([index, *q, *qd, *qdd, *mount, *gyro, *accel])
    header = ("arm,q1_rad,q2_rad,qd1_rad_s,qd2_rad_s,qdd1_rad_s2,qdd2_rad_s2,mount_x_m,mount_y_m,mount_z_m,"
              "gyro_x_rad_s,gyro_y_rad_s,gyro_z_rad_s,accel_x_m_s2,accel_y_m_s2,accel_z_m_s2")
    np.savetxt(os.path.join(HERE, "arm_imu.csv"), np.array(rows), delimiter=",", fmt="%.17g", header=header,
               comments="")


if __name__ == "__main__":
    main()
