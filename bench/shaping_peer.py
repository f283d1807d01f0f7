#!/usr/bin/python3
"""Offline shaping of a 10^6-sample signal: clearshape vs the NumPy/SciPy peers.

Same signal and same shaper (ZVD, 10 Hz, ζ = 0.1, 1 ms samples, impulse times between
samples). The peers, as in Vaughan's InputShaping.py, digitise the shaper into a dense
sequence (`digseq`: each impulse split linearly over its two neighbouring samples) and
  * numpy.convolve it with the input (held at both ends), and
  * scipy.signal.lfilter the same FIR (history initialised at rest at the first value);
a third, sparse NumPy peer sums the few non-zero taps as shifted whole-array products.
clearshape's time comes from `bench_shaping --benchmark_filter=BM_ShapeOffline/impulses:3`;
its output (bench_shaping --dump-offline) is checked against the peers before timing.

    /usr/bin/python3 bench/shaping_peer.py --build-dir build
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import timeit
from math import comb

import numpy as np
from scipy import signal

# The digitised shaper sequence (Vaughan's digseq) and its convolution, as the golden generator
# of the shaping tests builds them (same 1 ms sample time).
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "golden"))
from gen_apply import TS as GOLDEN_TS, digseq, shape_convolve  # noqa: E402

TS = 1e-3
assert TS == GOLDEN_TS
F_HZ = 10.0
ZETA = 0.1


def zvd_impulses():
    """Singer & Seering 1990: [1, 2K, K²]/(1+K)² at [0, Td/2, Td]."""
    k = np.exp(-ZETA * np.pi / np.sqrt(1 - ZETA**2))
    td = 1.0 / (F_HZ * np.sqrt(1 - ZETA**2))
    a = np.array([comb(2, i) * k**i for i in range(3)])
    return np.arange(3) * td / 2, a / a.sum()


def peer_lfilter(u, seq):
    d = len(seq) - 1
    zi = signal.lfilter_zi(seq, [1.0]) * u[0]
    y, _ = signal.lfilter(seq, [1.0], np.concatenate([u, np.full(d, u[-1])]), zi=zi)
    return y


def peer_sparse(u, seq):
    d = len(seq) - 1
    padded = np.concatenate([np.full(d, u[0]), u, np.full(d, u[-1])])
    n_out = len(u) + d
    y = np.zeros(n_out)
    for j in np.flatnonzero(seq):
        y += seq[j] * padded[d - j:d - j + n_out]
    return y


def median_ms(fn, repeat=7):
    times = timeit.repeat(fn, number=1, repeat=repeat)
    return 1e3 * float(np.median(times)), 1e3 * float(np.min(times))


def ours_ms(exe):
    out = subprocess.run(
        [exe, "--benchmark_filter=^BM_ShapeOffline/impulses:3$", "--benchmark_format=json",
         "--benchmark_repetitions=7", "--benchmark_report_aggregates_only=true"],
        check=True, capture_output=True, text=True).stdout
    scale = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}
    result = {}
    for b in json.loads(out)["benchmarks"]:
        if b.get("aggregate_name") in ("median", "mean"):
            unit = scale[b["time_unit"]]
            result[b["aggregate_name"]] = (b["real_time"] * unit, b["cpu_time"] * unit)
    return result["median"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build-dir", default="build")
    args = parser.parse_args()
    exe = os.path.join(args.build_dir, "bench", "bench_shaping")
    if not os.access(exe, os.X_OK):
        sys.exit(f"shaping_peer.py: {exe} not found; build the bench_shaping target first")

    with tempfile.TemporaryDirectory() as tmp:
        prefix = os.path.join(tmp, "offline")
        subprocess.run([exe, f"--dump-offline={prefix}"], check=True)
        u = np.fromfile(prefix + "_input.f64", dtype="<f8")
        y_ours = np.fromfile(prefix + "_output.f64", dtype="<f8")

    seq = digseq(*zvd_impulses())
    peers = {
        "numpy.convolve (dense digseq)": lambda: shape_convolve(u, seq),
        "scipy.signal.lfilter (same FIR)": lambda: peer_lfilter(u, seq),
        "numpy sparse shifted sum": lambda: peer_sparse(u, seq),
    }
    scale = max(1.0, float(np.max(np.abs(y_ours))))
    ok = True
    print(f"offline shaping, {len(u)} samples, ZVD 10 Hz ζ=0.1 at 1 ms: "
          f"{len(seq)}-long dense sequence, {np.count_nonzero(seq)} non-zero taps")
    for name, fn in peers.items():
        y = fn()
        diff = float(np.max(np.abs(y - y_ours))) / scale if len(y) == len(y_ours) else np.inf
        ok &= diff < 1e-12
        print(f"  agreement with {name:34s}: max |Δ|/max|y| = {diff:.1e}")
    if not ok:
        sys.exit("shaping_peer.py: outputs disagree (tolerance 1e-12)")

    ours_wall, ours_cpu = ours_ms(exe)
    print(f"  {'clearshape shape_offline':36s} {ours_wall:9.3f} ms (median wall; CPU {ours_cpu:.3f} ms)")
    for name, fn in peers.items():
        med, best = median_ms(fn)
        print(f"  {name:36s} {med:9.3f} ms (median; best {best:.3f})  "
              f"ratio {med / ours_wall:7.1f}x")


if __name__ == "__main__":
    main()
