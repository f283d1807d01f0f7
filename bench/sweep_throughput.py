"""Sweep throughput (docs/sweeps.md): simulated runs per second per core for the local engine
and for a Dask LocalCluster (worker processes on 127.0.0.1), the overhead per Dask task, and
the wall time of a 10⁶-run sweep projected from those figures.

    /usr/bin/python3 bench/sweep_throughput.py --build-dir build [--points 24] [--workers 2]

A point is two runs (unshaped and shaped) of `duration_s` simulated seconds.
"""
import argparse
import os
import sys
import tempfile
import time

DEFAULT_SWEEP = """
[sweep]
seed = 1
duration_s = {duration}
batch = {batch}
[fixed]
signal = "step"
amplitude = 20
design_frequency_hz = 6.5
zeta = 0.05
[grid]
clearance_deg = {clearances}
shaper = ["zv", "zvd", "ei"]
"""


def noop(x):
    return x


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build-dir", default="build")
    ap.add_argument("--points", type=int, default=24, help="points per measurement (multiple of 3)")
    ap.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--duration-s", type=float, default=5.0, help="simulated time per run (thesis: 5 s)")
    a = ap.parse_args()
    sys.path.insert(0, os.path.join(a.build_dir, "python"))
    from distributed import Client, LocalCluster

    from clearshape.sweep import run_sweep
    from clearshape.sweep_spec import Sweep

    clearances = [round(0.02 + 0.04 * i, 3) for i in range(max(1, a.points // 3))]
    text = DEFAULT_SWEEP.format(duration=a.duration_s, batch=4, clearances=clearances)
    sweep = Sweep(text, "bench.toml")
    runs = 2 * len(sweep.points())
    results = {}
    with tempfile.TemporaryDirectory() as tmp:
        for label, kwargs in [("local, 1 process", {"workers": 1}),
                              (f"local, {a.workers} processes", {"workers": a.workers})]:
            t0 = time.perf_counter()
            run_sweep(sweep, os.path.join(tmp, label.replace(" ", "_").replace(",", "")), quiet=True, **kwargs)
            results[label] = (time.perf_counter() - t0, kwargs["workers"])
        with LocalCluster(n_workers=a.workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                          dashboard_address=None) as cluster, Client(cluster) as client:
            client.run(lambda: __import__("clearshape"))  # import once per worker, outside the timing
            t0 = time.perf_counter()
            run_sweep(sweep, os.path.join(tmp, "dask"), scheduler=client, quiet=True)
            results[f"Dask LocalCluster, {a.workers} workers"] = (time.perf_counter() - t0, a.workers)
            n = 200
            t0 = time.perf_counter()
            client.gather(client.map(noop, range(n), pure=False))
            overhead_s = (time.perf_counter() - t0) / n
    print(f"sweep throughput: {len(sweep.points())} points = {runs} runs of {a.duration_s:g} s simulated, "
          f"batches of 4 points, {os.cpu_count()} cores")
    print(f"{'engine':34} {'wall_s':>8} {'runs/s':>8} {'runs/s/core':>12}")
    for label, (wall, cores) in results.items():
        print(f"{label:34} {wall:8.2f} {runs / wall:8.2f} {runs / wall / cores:12.2f}")
    print(f"Dask per-task overhead (no-op tasks, {n} of them): {overhead_s * 1e3:.2f} ms")
    per_core = runs / results["local, 1 process"][0]
    for workers in (8, 64, 512):
        # Projection: N workers at the single-process rate, unless the scheduler, handing out one
        # task per batch of 4 points (8 runs) at the measured no-op task rate, is the slower part.
        wall = max(1e6 / (per_core * workers), (1e6 / 8) * overhead_s)
        print(f"projected 10^6 runs on {workers:4d} workers: {wall / 3600:.2f} h")


if __name__ == "__main__":
    main()
