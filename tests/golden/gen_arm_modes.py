#!/usr/bin/python3
"""Golden data for the arm's linearised modes (tests/arm/test_modes.cpp).

Run with Debian's Python:  /usr/bin/python3 tests/golden/gen_arm_modes.py
Writes, next to this script:
  arm_scara_modes.csv  q2_rad, f1_hz, f2_hz (undamped, ascending), zeta1, zeta2,
                       share_1_1, share_2_1, share_1_2, share_2_2 (share_k_i: mode k in joint i)
                       of the built-in scara-2 (docs/arm.md) with its plays closed on the flanks

Independent of the C++ code (KDL's M(q), Eigen's generalised eigensolver): M(q) is the planar
closed form of gen_arm_scara.py; K = diag(3000, 1500) N·m/rad (the Hunt–Crossley flanks, n = 1,
whose damping vanishes in persistent contact) and C = diag(0.02, 0.01) N·m·s/rad (the bearings'
viscous friction). scipy.linalg.eigh(K, M) gives ω² and the mass-normalised shapes φ; the modal
damping is ζ = φᵀCφ/(2ω) and mode k's share in joint i's static response to its own gearbox
output is φ_k,i² K_i/ω_k². Cross-checked here before writing: the eigenvalues of the first-order
system [[0, I], [−M⁻¹K, −M⁻¹C]] (scipy.linalg.eig) give the same ω (|λ|) and ζ (−Re λ/|λ|) to
1e-9, and every joint's shares sum to 1. M does not depend on q1 (the base angle).
"""
import os

import numpy as np
from scipy import linalg

from gen_arm_scara import mass_closed_form

HERE = os.path.dirname(os.path.abspath(__file__))
K = np.diag([3000.0, 1500.0])
C = np.diag([0.02, 0.01])


def modes(q2):
    m = mass_closed_form(q2)
    w2, phi = linalg.eigh(K, m)  # ascending, φᵀ M φ = 1
    w = np.sqrt(w2)
    zeta = np.array([phi[:, k] @ C @ phi[:, k] / (2 * w[k]) for k in range(2)])
    share = phi**2 * np.diag(K)[:, None] / w2[None, :]  # [i, k]
    # cross-check against the first-order system's eigenvalues
    a = np.block([[np.zeros((2, 2)), np.eye(2)], [-linalg.solve(m, K), -linalg.solve(m, C)]])
    lam = linalg.eigvals(a)
    lam = lam[lam.imag > 0]
    lam = lam[np.argsort(np.abs(lam))]
    assert np.allclose(np.abs(lam), w, rtol=1e-9)
    assert np.allclose(-lam.real / np.abs(lam), zeta, rtol=1e-6)
    assert np.allclose(share.sum(axis=1), 1.0, atol=1e-12)
    return w / (2 * np.pi), zeta, share


def main():
    rows = []
    for q2 in np.linspace(-2.6, 2.6, 27):
        f, zeta, share = modes(q2)
        rows.append([q2, *f, *zeta, share[0, 0], share[0, 1], share[1, 0], share[1, 1]])
    np.savetxt(os.path.join(HERE, "arm_scara_modes.csv"), np.array(rows), delimiter=",", fmt="%.17g",
               header="q2_rad,f1_hz,f2_hz,zeta1,zeta2,share_1_1,share_2_1,share_1_2,share_2_2", comments="")


if __name__ == "__main__":
    main()
