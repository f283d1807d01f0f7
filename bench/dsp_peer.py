#!/usr/bin/python3
"""Thesis speed filter and Welch PSD on 10^6 samples: clearshape vs scipy.signal.

Same signal (bench_dsp --dump), same filter (butter(4, 30/(2π) Hz, fs=1000, output='sos')):
  * scipy.signal.sosfilt       vs BM_Sosfilt
  * scipy.signal.sosfiltfilt   vs BM_Sosfiltfilt
  * scipy.signal.welch (Hann, nperseg=1024)  vs BM_Welch
  * scipy.signal.butter(…, output='sos') design (order 4, 16) vs BM_ButterDesign
Outputs are checked against the peers before timing (tolerance 1e-10 relative). Times are
median CPU times (Google Benchmark cpu_time; time.process_time for the peer), single-threaded.

    /usr/bin/python3 bench/dsp_peer.py --build-dir build
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
import timeit

import numpy as np
from scipy import signal

FS = 1000.0
CUTOFF_HZ = 30.0 / (2.0 * math.pi)


def median_ms(fn, repeat=7):
    # CPU time of this process (the machine may be shared; wall time would count waiting).
    times = timeit.repeat(fn, number=1, repeat=repeat, timer=time.process_time)
    return 1e3 * float(np.median(times))


def ours_ms(exe):
    out = subprocess.run(
        [exe, "--benchmark_filter=^BM_(Sosfilt|Sosfiltfilt|Welch|ButterDesign/4|ButterDesign/16)$",
         "--benchmark_format=json", "--benchmark_repetitions=5",
         "--benchmark_report_aggregates_only=true"],
        check=True, capture_output=True, text=True).stdout
    scale = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}
    result = {}
    for b in json.loads(out)["benchmarks"]:
        if b.get("aggregate_name") == "median":
            result[b["run_name"]] = b["cpu_time"] * scale[b["time_unit"]]
    return result


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build-dir", default="build")
    args = parser.parse_args()
    exe = os.path.join(args.build_dir, "bench", "bench_dsp")
    if not os.access(exe, os.X_OK):
        sys.exit(f"dsp_peer.py: {exe} not found; build the bench_dsp target first")

    with tempfile.TemporaryDirectory() as tmp:
        prefix = os.path.join(tmp, "dsp")
        subprocess.run([exe, f"--dump={prefix}"], check=True)
        load = lambda name: np.fromfile(f"{prefix}_{name}.f64", dtype="<f8")  # noqa: E731
        x, y_causal, y_zero, psd = load("input"), load("sosfilt"), load("sosfiltfilt"), load("welch")

    sos = signal.butter(4, CUTOFF_HZ, fs=FS, output="sos")
    peers = {
        "BM_Sosfilt": ("scipy.signal.sosfilt", lambda: signal.sosfilt(sos, x), y_causal),
        "BM_Sosfiltfilt": ("scipy.signal.sosfiltfilt", lambda: signal.sosfiltfilt(sos, x), y_zero),
        "BM_Welch": ("scipy.signal.welch nperseg=1024", lambda: signal.welch(x, FS, nperseg=1024)[1], psd),
        "BM_ButterDesign/4": ("scipy.signal.butter N=4 sos", lambda: signal.butter(4, 4.77, fs=FS, output="sos"), None),
        "BM_ButterDesign/16": ("scipy.signal.butter N=16 sos", lambda: signal.butter(16, 4.77, fs=FS, output="sos"), None),
    }
    ok = True
    print(f"dsp on {len(x)} samples at 1 kHz; thesis filter = butter(4, 30 rad/s) as SOS")
    for key, (name, fn, ours) in peers.items():
        if ours is None:
            continue
        ref = fn()
        diff = float(np.max(np.abs(ref - ours)) / np.max(np.abs(ref)))
        ok &= diff < 1e-10
        print(f"  agreement with {name:34s}: max |Δ|/max|ref| = {diff:.1e}")
    if not ok:
        sys.exit("dsp_peer.py: outputs disagree (tolerance 1e-10)")

    ours = ours_ms(exe)
    for key, (name, fn, _) in peers.items():
        if key not in ours:
            continue
        theirs = median_ms(fn)
        print(f"  {key:20s} clearshape {ours[key]:9.4f} ms | {name:32s} {theirs:9.4f} ms | "
              f"ratio {theirs / ours[key]:6.1f}x")


if __name__ == "__main__":
    main()
