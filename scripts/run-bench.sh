#!/usr/bin/env bash
# Runs every Google Benchmark executable, then every peer script in bench/ (which time the
# SciPy/NumPy peer on the same work and print the speed ratio). Results also go to
# $build_dir/bench/*.json.
set -euo pipefail
build_dir="${1:-build}"
for exe in "$build_dir"/bench/bench_*; do
  [[ -x "$exe" ]] || continue
  name="$(basename "$exe")"
  echo "== $name" >&2
  "$exe" --benchmark_out="$build_dir/bench/$name.json" --benchmark_out_format=json \
         --benchmark_repetitions="${BENCH_REPETITIONS:-5}" --benchmark_report_aggregates_only=true
done
for script in bench/*.py; do
  [[ -f "$script" ]] || continue
  echo "== $script" >&2
  /usr/bin/python3 "$script" --build-dir "$build_dir"
done
