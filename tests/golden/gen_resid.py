#!/usr/bin/python3
"""Golden data for clearshape's residual tests (ident/residuals.hpp), computed with NumPy/SciPy.

Run with Debian's Python:   /usr/bin/python3 tests/golden/gen_resid.py
Writes tests/golden/ident_resid.json (committed; CI never regenerates it). statsmodels is not a
Debian 12 dependency of the project, so the Ljung–Box statistic is written out here from its
definition (Ljung & Box 1978) with scipy.stats.chi2 for the p-value, and the
input–residual test from Ljung, System Identification, 2nd ed., §16.6. If statsmodels is
installed, its acorr_ljungbox is checked against the NumPy value before anything is written.
"""
import json
import os

import numpy as np
import scipy
from scipy import signal, stats

HERE = os.path.dirname(os.path.abspath(__file__))


def cov(a, b, lag):
    """Biased R_ab(lag) = (1/N) sum_t a(t) b(t - lag), any sign of lag."""
    n = len(a)
    if lag >= 0:
        return float(np.dot(a[lag:], b[:n - lag])) / n
    return float(np.dot(a[:n + lag], b[-lag:])) / n


def acf(x, max_lag):
    x = x - x.mean()
    r0 = cov(x, x, 0)
    return np.array([cov(x, x, k) / r0 for k in range(max_lag + 1)])


def whiteness(e, m, z, p_model=0):
    n = len(e)
    r = acf(e, m)
    q = n * (n + 2) * np.sum(r[1:] ** 2 / (n - np.arange(1, m + 1)))
    dof = m - p_model
    try:  # optional cross-check against statsmodels
        from statsmodels.stats.diagnostic import acorr_ljungbox
        ref = acorr_ljungbox(e, lags=[m], model_df=p_model, return_df=True)
        assert abs(float(ref["lb_stat"].iloc[0]) - q) <= 1e-9 * q
    except ImportError:
        pass
    return {"correlation": r.tolist(), "band": z / np.sqrt(n), "statistic": float(q), "dof": dof,
            "p_value": float(stats.chi2.sf(q, dof))}


def independence(u, e, m, z):
    n = len(e)
    uc, ec = u - u.mean(), e - e.mean()
    scale = np.sqrt(cov(ec, ec, 0) * cov(uc, uc, 0))
    lags = np.arange(-m, m + 1)
    r = np.array([cov(ec, uc, k) / scale for k in lags])
    # Every lag of the biased autocorrelations, -(N-1) ... N-1, then P(d) = sum_k re(k) ru(k + d) directly.
    re = np.correlate(ec, ec, mode="full") / (n * cov(ec, ec, 0))
    ru = np.correlate(uc, uc, mode="full") / (n * cov(uc, uc, 0))
    ru = np.concatenate((ru, np.zeros(2 * m)))
    kernel = np.array([np.dot(re, ru[d:d + 2 * n - 1]) for d in range(2 * m + 1)])
    p = kernel[np.abs(np.subtract.outer(np.arange(2 * m + 1), np.arange(2 * m + 1)))]
    lam, vec = np.linalg.eigh(p)
    keep = lam > 1e-10 * lam.max()
    proj = vec[:, keep].T @ r
    stat = float(n * np.sum(proj ** 2 / lam[keep]))
    dof = int(keep.sum())
    return {"correlation": r.tolist(), "band": float(z * np.sqrt(kernel[0] / n)), "statistic": stat, "dof": dof,
            "p_value": float(stats.chi2.sf(stat, dof))}


def main():
    rng = np.random.default_rng(16061978)
    n = 2000
    m = 25
    z = float(stats.norm.ppf(0.995))
    # A coloured input (low-passed noise) and three residuals: white and independent; AR(1)
    # (not white); white plus a filtered copy of the input (missing dynamics: not independent).
    b, a = signal.butter(2, 0.1)
    u = signal.lfilter(b, a, rng.standard_normal(n))
    white = rng.standard_normal(n)
    ar1 = signal.lfilter([1.0], [1.0, -0.6], rng.standard_normal(n))
    leaky = rng.standard_normal(n) + 3.0 * signal.lfilter([0.0, 0.5, 0.3], [1.0], u)
    cases = []
    for name, e in (("white", white), ("ar1", ar1), ("input_leak", leaky)):
        cases.append({"name": name, "residual": e.tolist(), "whiteness": whiteness(e, m, z),
                      "independence": independence(u, e, m, z)})
    ar1_p2 = whiteness(ar1, m, z, p_model=2)
    payload = {"generator": "tests/golden/gen_resid.py", "scipy": scipy.__version__, "numpy": np.__version__,
               "max_lag": m, "confidence": 0.99, "z": z, "input": u.tolist(), "cases": cases,
               "ar1_model_parameters_2": ar1_p2}
    path = os.path.join(HERE, "ident_resid.json")
    with open(path, "w") as out:
        json.dump(payload, out, separators=(",", ":"))
        out.write("\n")
    print(f"wrote {path} ({os.path.getsize(path)} bytes)")
    for c in cases:
        print(c["name"], "white p", c["whiteness"]["p_value"], "indep p", c["independence"]["p_value"])


if __name__ == "__main__":
    main()
