#!/usr/bin/python3
"""One clearance-aware design case: clearshape's fixed-step simulator vs SciPy's solve_ivp.

The case is the 20° step on the worn-coupling rig (docs/worn-coupling.md), 1.25 s, the work one
evaluation of the design repeats for every move × start place × model point. The SciPy peer is the
independent dead-zone model of tests/golden/gen_worn_coupling.py (thesis drive, 1° play, linear
flank, bearing Coulomb + viscous; DOP853 one input sample at a time) under the drive command
clearshape's rig applied (`clearshape simulate --rig worn-coupling`). clearshape's time is
BM_DesignCaseFixedStep of bench_clearance_aware (CPU time per case; BM_DesignCaseCvode beside
it). Prints both, the ratio, and what the issue's design (300 evaluations × 60 cases) would cost.

    /usr/bin/python3 bench/clearance_aware_peer.py --build-dir build
"""
import argparse
import csv
import importlib.util
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np
from scipy import integrate

HERE = os.path.dirname(os.path.abspath(__file__))


def golden_model():
    path = os.path.join(HERE, "..", "tests", "golden", "gen_worn_coupling.py")
    spec = importlib.util.spec_from_file_location("gen_worn_coupling", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def scipy_case(g, drive_deg, fraction):
    y = np.zeros(g.ND + 2)
    y[g.ND] = fraction * g.BETA
    for k in range(1, len(drive_deg)):
        sol = integrate.solve_ivp(g.rhs, ((k - 1) * g.TS, k * g.TS), y, method="DOP853", rtol=1e-8,
                                  atol=1e-11, args=(drive_deg[k - 1],))
        y = sol.y[:, -1]
    return y


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build-dir", default="build")
    args = ap.parse_args()
    cli = os.path.join(args.build_dir, "bin", "clearshape")
    bench = os.path.join(args.build_dir, "bench", "bench_clearance_aware")
    for exe in (cli, bench):
        if not os.path.exists(exe):
            sys.exit(f"clearance_aware_peer: {exe} not found; build it first")
    timing = json.loads(subprocess.run([bench, "--benchmark_format=json", "--benchmark_filter=DesignCase"],
                                       check=True, capture_output=True, text=True).stdout)
    ours = {b["run_name"]: b["cpu_time"] * {"ms": 1e-3, "us": 1e-6, "ns": 1e-9, "s": 1.0}[b["time_unit"]]
            for b in timing["benchmarks"]}
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "case.csv")
        subprocess.run([cli, "simulate", "--rig", "worn-coupling", "--signal", "step", "--amplitude", "20",
                        "--start-s", "0.05", "--duration", "1.25", "--no-noise", "--initial-play", "-1", "-o", out],
                       check=True, capture_output=True)
        with open(out) as f:
            drive = np.array([float(r["drive_command_deg"]) for r in csv.DictReader(f)])
    g = golden_model()
    begin = time.process_time()
    scipy_case(g, drive, -1.0)
    scipy_s = time.process_time() - begin
    fixed, cvode = ours["BM_DesignCaseFixedStep"], ours["BM_DesignCaseCvode"]
    print(f"{'one design case (CPU)':<28}{'s':>10}{'SciPy / it':>12}")
    print(f"{'clearshape fixed step':<28}{fixed:>10.5f}{scipy_s / fixed:>12.0f}")
    print(f"{'clearshape CVODE':<28}{cvode:>10.5f}{scipy_s / cvode:>12.0f}")
    print(f"{'SciPy solve_ivp (DOP853)':<28}{scipy_s:>10.5f}{1.0:>12.0f}")
    cases = 300 * 60
    print(f"the issue's design, 300 evaluations x 60 cases on one core: clearshape {cases * fixed:.1f} s, "
          f"SciPy {cases * scipy_s / 3600:.1f} h")


if __name__ == "__main__":
    main()
