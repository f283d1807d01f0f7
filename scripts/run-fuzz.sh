#!/usr/bin/env bash
# Runs every libFuzzer target of a fuzz build for a bounded time and prints one line per target.
# New inputs go to <build>/corpus/<target>/ (the committed seeds in fuzz/corpus/ are read only);
# a crash, a sanitizer report or an input slower than 10 s is written to <build>/artifacts/ and
# makes this script exit 1. Reproduce one with: <build>/fuzz/fuzz_<target> <artifact>
# Usage: scripts/run-fuzz.sh BUILD_DIR SECONDS [RUNS]   (RUNS: stop a target after that many)
set -uo pipefail
build=${1:?build dir}
seconds=${2:?seconds per target}
runs=${3:--1}
root=$(cd "$(dirname "$0")/.." && pwd)
status=0
mkdir -p "$build/artifacts"
for target in csv protocol rig_config impulses modes; do
  work="$build/corpus/$target"
  mkdir -p "$work"
  log="$build/fuzz_$target.log"
  extra=()
  # modes: at most 128 samples per record (fuzz/fuzz_modes.cpp), about 7 ms of CPU per execution
  [[ $target == modes ]] && extra=(-max_len=257)
  "$build/fuzz/fuzz_$target" -max_total_time="$seconds" -runs="$runs" -timeout=10 -print_final_stats=1 \
    "${extra[@]}" -artifact_prefix="$build/artifacts/${target}-" "$work" "$root/fuzz/corpus/$target" > "$log" 2>&1
  rc=$?
  executed=$(grep -E '^stat::number_of_executed_units' "$log" | awk '{print $2}')
  rate=$(grep -E '^stat::average_exec_per_sec' "$log" | awk '{print $2}')
  echo "fuzz_$target: ${executed:-?} executions (${rate:-?}/s), exit $rc (log $log)"
  [[ $rc -eq 0 ]] || status=1
done
exit $status
