#!/usr/bin/python3
"""P3UZ identification: clearshape vs scipy.optimize.least_squares on the same problem.

The data are the benchmark's own (bench_ident --dump): the thesis speed-mode model (Eq. 4.2) on
5 s records at 1 kHz with 1 % noise — one PRBS run, and four runs (PRBS, step, ramp, sine).
The peer solves the same simulation-error problem — ŷ = scipy.signal.lsim (zero-order hold,
zero initial state) of Kp(1 + Tz s)/((1 + 2ζTw s + Tw² s²)(1 + Tp3 s)), θ = (Kp, ln Tp3, ln Tw,
ln ζ, Tz), residuals weighted by 1/√(N var y) per run — with least_squares (Levenberg–Marquardt,
finite-difference Jacobian) from the truth × 1.15, the start of BM_RefineP3UZ. The optima are
checked to agree before timing. BM_FitP3UZ (the full fit: candidates ranked from the data,
multi-start) has no SciPy counterpart; its time is printed for reference.

    /usr/bin/python3 bench/ident_peer.py --build-dir build
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import timeit

import numpy as np
from scipy import optimize, signal

DT = 1e-3
TRUTH = {"Kp": 25.47, "Tp3": 0.0857, "Tw": 0.0479, "Zeta": 0.2880, "Tz": -0.0398}


def simulate(theta, t, u):
    kp, ltp3, ltw, lz, tz = theta
    tp3, tw, z = np.exp(ltp3), np.exp(ltw), np.exp(lz)
    num = [kp * tz, kp]
    den = np.polymul([tw * tw, 2.0 * z * tw, 1.0], [tp3, 1.0])
    return signal.lsim((num, den), u, t, interp=False)[1]


def peer_fit(runs):
    start = np.array([1.15 * TRUTH["Kp"], np.log(1.15 * TRUTH["Tp3"]), np.log(1.15 * TRUTH["Tw"]),
                      np.log(1.15 * TRUTH["Zeta"]), 1.15 * TRUTH["Tz"]])
    weights = [1.0 / np.sqrt(len(y) * np.var(y)) for _, y in runs]
    ts = [np.arange(len(u)) * DT for u, _ in runs]

    def residuals(theta):
        return np.concatenate([w * (simulate(theta, t, u) - y) for (u, y), t, w in zip(runs, ts, weights)])

    res = optimize.least_squares(residuals, start, method="lm", xtol=1e-12, ftol=1e-12, gtol=1e-12)
    th = res.x
    return res, {"Kp": th[0], "Tp3": np.exp(th[1]), "Tw": np.exp(th[2]), "Zeta": np.exp(th[3]), "Tz": th[4]}


def ours_ms(exe):
    out = subprocess.run(
        [exe, "--benchmark_filter=^BM_(Fit|Refine)P3UZ", "--benchmark_format=json",
         "--benchmark_repetitions=5", "--benchmark_report_aggregates_only=true"],
        check=True, capture_output=True, text=True).stdout
    scale = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}
    result = {}
    for b in json.loads(out)["benchmarks"]:
        if b.get("aggregate_name") == "median":
            result[b["run_name"]] = (b["real_time"] * scale[b["time_unit"]], b["cpu_time"] * scale[b["time_unit"]])
    return result


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build-dir", default="build")
    args = parser.parse_args()
    exe = os.path.join(args.build_dir, "bench", "bench_ident")
    if not os.access(exe, os.X_OK):
        sys.exit(f"ident_peer.py: {exe} not found; build the bench_ident target first")

    with tempfile.TemporaryDirectory() as tmp:
        prefix = os.path.join(tmp, "ident")
        subprocess.run([exe, f"--dump={prefix}"], check=True)
        runs = [(np.fromfile(f"{prefix}_u{e}.f64", dtype="<f8"), np.fromfile(f"{prefix}_y{e}.f64", dtype="<f8"))
                for e in range(4)]
        ours_fit = {n: json.load(open(f"{prefix}_fit{n}.json")) for n in (1, 4)}

    ours = ours_ms(exe)
    print("P3UZ simulation-error fit, 5 s at 1 kHz per run (5001 samples), thesis speed model + 1 % noise")
    ok = True
    for n in (1, 4):
        res, params = peer_fit(runs[:n])
        worst = max(abs(params[k] - ours_fit[n][k]) / abs(params[k]) for k in params)
        ok &= worst < 1e-5
        peer_times = timeit.repeat(lambda: peer_fit(runs[:n]), number=1, repeat=3)
        peer = 1e3 * float(np.median(peer_times))
        refine_wall, refine_cpu = ours[f"BM_RefineP3UZ/experiments:{n}"]
        fit_wall, fit_cpu = ours[f"BM_FitP3UZ/experiments:{n}"]
        print(f"\n  {n} run(s): optima agree to {worst:.1e} (relative); SciPy used {res.nfev} residual evaluations "
              f"(its finite-difference Jacobians included)")
        print(f"    clearshape refine (one LM run, exact sensitivities) {refine_wall:9.2f} ms wall ({refine_cpu:.2f} ms CPU)")
        print(f"    scipy least_squares 'lm' + signal.lsim            {peer:9.2f} ms          ratio {peer / refine_wall:6.1f}x")
        print(f"    clearshape full fit (ranked candidates, 3 starts)   {fit_wall:9.2f} ms wall ({fit_cpu:.2f} ms CPU)")
    if not ok:
        sys.exit("ident_peer.py: the optima disagree (tolerance 1e-5 relative)")


if __name__ == "__main__":
    main()
