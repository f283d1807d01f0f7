#!/usr/bin/python3
"""Golden data for the arm module's rigid-body part (tests/arm/test_chain.cpp).

Run with Debian's Python:  /usr/bin/python3 tests/golden/gen_arm_scara.py
Writes, next to this script:
  arm_scara_mass.csv        q1_rad, q2_rad, m11, m12, m22 (kg·m²), tool_x_m, tool_y_m, tool_z_m
                            of the built-in scara-2 (docs/arm.md)
  arm_vertical_gravity.csv  q1_rad, q2_rad, g1, g2 (N·m) of the built-in vertical-2

Independent of the C++ code (which takes M(q) from Orocos KDL's composite-rigid-body solver):
the planar two-link closed form (Spong, Hutchinson & Vidyasagar, Robot Modeling and Control,
2006, §7.4.1) with every rigid body (link, payload) contributing
  on link 1 at distance d:  M11 += I + m d²
  on link 2 at distance d:  M11 += I + m (L1² + d² + 2 L1 d cos q2),
                            M12 += I + m (d² + L1 d cos q2),  M22 += I + m d²,
cross-checked here against M = Σ m J_vᵀ J_v + I J_ωᵀ J_ω from each body's Jacobian, built
numerically with NumPy (the two must agree to 1e-12 before anything is written).
The gravity torque of vertical-2 is g(q) = ∂V/∂q of V = Σ m g z_c(q), and is cross-checked
against a central difference of V.
"""
import os

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
G = 9.80665

# scara-2 (the built-in URDF): rods of radius 20 mm, izz about the centre of mass
L1, L2 = 0.25, 0.20
BODIES_SCARA = [  # (link, mass kg, distance from its joint m, izz kg·m²)
    (1, 2.0, 0.125, 2.0 * (3 * 0.02**2 + 0.25**2) / 12),
    (2, 1.0, 0.100, 1.0 * (3 * 0.02**2 + 0.20**2) / 12),
    (2, 0.5, 0.200, 1e-6),  # payload at the tool
]
TOOL_Z = 0.2  # the shoulder's height

# vertical-2: axes along y, links in the x–z plane
VL1, VL2, VH = 0.30, 0.25, 0.4
BODIES_VERTICAL = [(1, 1.5, 0.15), (2, 0.8, 0.125), (2, 0.3, 0.25)]


def mass_closed_form(q2):
    m = np.zeros((2, 2))
    c = np.cos(q2)
    for link, mass, d, izz in BODIES_SCARA:
        if link == 1:
            m[0, 0] += izz + mass * d * d
        else:
            m[0, 0] += izz + mass * (L1 * L1 + d * d + 2 * L1 * d * c)
            m[0, 1] += izz + mass * (d * d + L1 * d * c)
            m[1, 1] += izz + mass * d * d
    m[1, 0] = m[0, 1]
    return m


def mass_from_jacobians(q1, q2):
    m = np.zeros((2, 2))
    for link, mass, d, izz in BODIES_SCARA:
        if link == 1:
            jv = np.array([[-d * np.sin(q1), 0.0], [d * np.cos(q1), 0.0]])
            jw = np.array([1.0, 0.0])
        else:
            s12, c12 = np.sin(q1 + q2), np.cos(q1 + q2)
            jv = np.array([[-L1 * np.sin(q1) - d * s12, -d * s12], [L1 * np.cos(q1) + d * c12, d * c12]])
            jw = np.array([1.0, 1.0])
        m += mass * jv.T @ jv + izz * np.outer(jw, jw)
    return m


def tool(q1, q2):
    return (L1 * np.cos(q1) + L2 * np.cos(q1 + q2), L1 * np.sin(q1) + L2 * np.sin(q1 + q2), TOOL_Z)


def vertical_potential(q1, q2):
    v = 0.0
    for link, mass, d in BODIES_VERTICAL:  # rotation about +y takes x to −z: z = h − r sin q
        z = VH - d * np.sin(q1) if link == 1 else VH - VL1 * np.sin(q1) - d * np.sin(q1 + q2)
        v += mass * G * z
    return v


def vertical_gravity(q1, q2):
    g1 = g2 = 0.0
    for link, mass, d in BODIES_VERTICAL:
        if link == 1:
            g1 -= mass * G * d * np.cos(q1)
        else:
            g1 -= mass * G * (VL1 * np.cos(q1) + d * np.cos(q1 + q2))
            g2 -= mass * G * d * np.cos(q1 + q2)
    return g1, g2


def main():
    grid = [(q1, q2) for q1 in (-1.1, 0.0, 0.7) for q2 in np.linspace(-2.5, 2.5, 11)]
    rows = []
    for q1, q2 in grid:
        m = mass_closed_form(q2)
        assert np.allclose(m, mass_from_jacobians(q1, q2), rtol=1e-12, atol=1e-15)
        rows.append([q1, q2, m[0, 0], m[0, 1], m[1, 1], *tool(q1, q2)])
    np.savetxt(os.path.join(HERE, "arm_scara_mass.csv"), np.array(rows), delimiter=",", fmt="%.17g",
               header="q1_rad,q2_rad,m11_kg_m2,m12_kg_m2,m22_kg_m2,tool_x_m,tool_y_m,tool_z_m", comments="")
    rows = []
    h = 1e-6
    for q1, q2 in grid:
        g1, g2 = vertical_gravity(q1, q2)
        d1 = (vertical_potential(q1 + h, q2) - vertical_potential(q1 - h, q2)) / (2 * h)
        d2 = (vertical_potential(q1, q2 + h) - vertical_potential(q1, q2 - h)) / (2 * h)
        assert abs(g1 - d1) < 1e-7 and abs(g2 - d2) < 1e-7
        rows.append([q1, q2, g1, g2])
    np.savetxt(os.path.join(HERE, "arm_vertical_gravity.csv"), np.array(rows), delimiter=",", fmt="%.17g",
               header="q1_rad,q2_rad,g1_n_m,g2_n_m", comments="")


if __name__ == "__main__":
    main()
