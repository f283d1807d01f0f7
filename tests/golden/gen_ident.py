#!/usr/bin/python3
"""Golden data for the ident module, from an independent SciPy/NumPy implementation.

Run with Debian's Python (numpy, scipy):  /usr/bin/python3 tests/golden/gen_ident.py
Writes (all small, committed; CI never regenerates them):
  ident_speed_step.csv     thesis speed-mode model (Eq. 4.2), unit step, 1 % white noise (seed 11)
  ident_position_prbs.csv  thesis position-mode model (Eq. 4.2), ±1 PRBS, 2 % noise (seed 12)
  ident_free_decay.csv     two damped sinusoids + offset + noise (a gyro free decay, seed 13)
  ident_expected.json      the SciPy fits of the same problems (see below)

Process models: the P3UZ simulation-error problem  min Σ (y − ŷ(θ))²,  ŷ = scipy.signal.lsim of
Kp(1 + Tz s)/((1 + 2ζTw s + Tw² s²)(1 + Tp3 s)) with a zero-order hold (interp=False), zero initial
state, θ = (Kp, ln Tp3, ln Tw, ln ζ, Tz); scipy.optimize.least_squares (method 'lm', finite-
difference Jacobian), started from the truth scaled by 1.15. Standard deviations from
(JᵀJ)⁻¹ σ², σ² = Σe²/(N − p), mapped to natural units (σ_T = T σ_lnT).

Modes: ERA (Ho–Kalman) in NumPy on the free decay (Hankel SVD, shift invariance), then
least_squares on y[k] = Σ rᵢᵏ (aᵢ cos kθᵢ − bᵢ sin kθᵢ) + c started from the ERA poles with the
amplitudes solved linearly; ωn = |ln z|/T, ζ = −ln|z|/|ln z|.
"""
import json
import os

import numpy as np
from scipy import optimize, signal

HERE = os.path.dirname(os.path.abspath(__file__))
DT = 1e-3


def p3uz(kp, tp3, tw, zeta, tz):
    num = [kp * tz, kp]
    den = np.polymul([tw * tw, 2.0 * zeta * tw, 1.0], [tp3, 1.0])
    return num, den


def simulate(theta, t, u):
    kp, ltp3, ltw, lz, tz = theta
    num, den = p3uz(kp, np.exp(ltp3), np.exp(ltw), np.exp(lz), tz)
    _, y, _ = signal.lsim((num, den), u, t, interp=False)
    return y


def fit_process(t, u, y, truth):
    kp, tp3, tw, zeta, tz = truth
    start = np.array([kp * 1.15, np.log(tp3 * 1.15), np.log(tw * 1.15), np.log(zeta * 1.15), tz * 1.15])
    res = optimize.least_squares(lambda th: simulate(th, t, u) - y, start, method="lm",
                                 xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=4000)
    th = res.x
    e = res.fun
    n, p = len(y), len(th)
    sigma2 = float(e @ e) / (n - p)
    cov = np.linalg.inv(res.jac.T @ res.jac) * sigma2
    sd = np.sqrt(np.diag(cov))
    values = {"Kp": th[0], "Tp3": np.exp(th[1]), "Tw": np.exp(th[2]), "Zeta": np.exp(th[3]), "Tz": th[4]}
    std = {"Kp": sd[0], "Tp3": np.exp(th[1]) * sd[1], "Tw": np.exp(th[2]) * sd[2],
           "Zeta": np.exp(th[3]) * sd[3], "Tz": sd[4]}
    yhat = y + e
    fit = 100.0 * (1.0 - np.linalg.norm(y - yhat) / np.linalg.norm(y - y.mean()))
    return {"parameters": {k: float(v) for k, v in values.items()},
            "std": {k: float(v) for k, v in std.items()},
            "sse": float(e @ e), "fit_percent": float(fit), "nfev": int(res.nfev), "status": int(res.status)}


def prbs(n, hold, seed):
    rng = np.random.default_rng(seed)
    u = np.empty(n)
    level = 1.0
    for k in range(n):
        if k % hold == 0 and rng.integers(0, 2) == 1:
            level = -level
        u[k] = level
    return u


def process_case(name, truth, u, noise, seed):
    t = np.arange(len(u)) * DT
    num, den = p3uz(*truth)
    _, y0, _ = signal.lsim((num, den), u, t, interp=False)
    rng = np.random.default_rng(seed)
    y = y0 + noise * np.sqrt(np.mean(y0 ** 2)) * rng.standard_normal(len(y0))
    path = os.path.join(HERE, f"ident_{name}.csv")
    np.savetxt(path, np.c_[t, u, y], delimiter=",", header="time_s,command,response", comments="", fmt="%.17g")
    result = fit_process(t, u, y, truth)
    result["truth"] = dict(zip(["Kp", "Tp3", "Tw", "Zeta", "Tz"], truth))
    result["noise_fraction_of_rms"] = noise
    return result


def era(y, order, rows):
    cols = len(y) - rows + 1
    h = np.array([y[r:r + cols] for r in range(rows)])
    u, s, vt = np.linalg.svd(h, full_matrices=False)
    g = u[:, :order] * np.sqrt(s[:order])
    a = np.linalg.lstsq(g[:-1], g[1:], rcond=None)[0]
    return np.linalg.eigvals(a)


def free_decay_case():
    modes = [(6.2, 0.03, 40.0, 0.4), (17.5, 0.012, 15.0, -1.0)]
    n, offset, noise = 2500, 0.3, 2.0
    k = np.arange(n)
    t = k * DT
    y0 = offset + sum(a * np.exp(-z * 2 * np.pi * f * t) * np.cos(2 * np.pi * f * np.sqrt(1 - z * z) * t + ph)
                      for f, z, a, ph in modes)
    rng = np.random.default_rng(13)
    y = y0 + noise * rng.standard_normal(n)
    np.savetxt(os.path.join(HERE, "ident_free_decay.csv"), np.c_[t, y], delimiter=",",
               header="time_s,link_rate_deg_s", comments="", fmt="%.17g")
    # ERA on the record with the offset as a pole at z = 1 (order 5), every 5th sample averaged.
    q = 5
    yd = y[: (n // q) * q].reshape(-1, q).mean(axis=1)
    zq = era(yd, 5, 80)
    z = np.exp(np.log(zq.astype(complex)) / q)
    pairs = sorted([p for p in z if p.imag > 1e-9], key=lambda p: np.angle(p))

    def basis(lr, th):
        r = np.exp(lr)
        return r ** k * np.cos(th * k), -(r ** k) * np.sin(th * k)

    def model(x):
        out = np.full(n, x[-1])
        for i in range(2):
            lr, th, a, b = x[4 * i:4 * i + 4]
            c, s = basis(lr, th)
            out += a * c + b * s
        return out

    # Amplitudes and offset by linear least squares with the ERA poles, then everything together.
    cols = []
    for p in pairs:
        c, s = basis(np.log(abs(p)), np.angle(p))
        cols += [c, s]
    cols.append(np.ones(n))
    amp = np.linalg.lstsq(np.array(cols).T, y, rcond=None)[0]
    x0 = []
    for i, p in enumerate(pairs):
        x0 += [np.log(abs(p)), np.angle(p), amp[2 * i], amp[2 * i + 1]]
    x0.append(amp[-1])
    res = optimize.least_squares(lambda x: model(x) - y, np.array(x0), method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15)
    x = res.x
    e = res.fun
    sigma2 = float(e @ e) / (n - len(x))
    cov = np.linalg.inv(res.jac.T @ res.jac) * sigma2
    out = []
    for i in range(2):
        lr, th, a, b = x[4 * i:4 * i + 4]
        rho = np.hypot(lr, th)
        wn = rho / DT
        zeta = -lr / rho
        gw = np.array([lr / (rho * DT), th / (rho * DT)])
        gz = np.array([-th * th / rho ** 3, lr * th / rho ** 3])
        c2 = cov[4 * i:4 * i + 2, 4 * i:4 * i + 2]
        amp_i = np.hypot(a, b)
        ga = np.array([a, b]) / amp_i
        ca = cov[4 * i + 2:4 * i + 4, 4 * i + 2:4 * i + 4]
        out.append({"frequency_hz": wn / (2 * np.pi), "frequency_std_hz": float(np.sqrt(gw @ c2 @ gw)) / (2 * np.pi),
                    "damping_ratio": zeta, "damping_ratio_std": float(np.sqrt(gz @ c2 @ gz)),
                    "amplitude": amp_i, "amplitude_std": float(np.sqrt(ga @ ca @ ga))})
    return {"truth": [{"frequency_hz": f, "damping_ratio": z, "amplitude": a} for f, z, a, _ in modes],
            "era_poles_full_rate": [[float(p.real), float(p.imag)] for p in pairs],
            "modes": [{k2: float(v) for k2, v in m.items()} for m in out],
            "offset": float(x[-1]), "sse": float(e @ e)}


def main():
    speed = (25.47, 0.0857, 0.0479, 0.2880, -0.0398)
    position = (0.9959, 0.0034, 0.0102, 0.9968, 0.0042)
    expected = {
        "generator": "tests/golden/gen_ident.py (numpy %s, scipy %s)" % (np.__version__, __import__("scipy").__version__),
        "speed_step": process_case("speed_step", speed, np.ones(3001), 0.01, 11),
        "position_prbs": process_case("position_prbs", position, prbs(2001, 15, 7), 0.02, 12),
        "free_decay": free_decay_case(),
    }
    with open(os.path.join(HERE, "ident_expected.json"), "w") as f:
        json.dump(expected, f, indent=2)
        f.write("\n")
    print(json.dumps(expected, indent=2))


if __name__ == "__main__":
    main()
