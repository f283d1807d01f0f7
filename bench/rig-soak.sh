#!/usr/bin/env bash
# Rig soak (not part of `make test` or `make bench`): rig::RealtimeRunner at 1 kHz over the
# board — the firmware ELF in clearshape-rig-emulator, paced at real time, over its pty — and
# over the simulated rig (rig::SimRig), DURATION seconds each; during each run cyclictest
# (Debian rt-tests: one SCHED_FIFO thread, 1 ms clock_nanosleep) measures the machine's own
# wake-up latency, so the runner's figures sit beside the machine's. Prints a Markdown table
# and keeps the raw figures in OUT_DIR.
#
#   bench/rig-soak.sh [DURATION_S=600] [BUILD_DIR=build] [OUT_DIR=out/rig-soak]
set -euo pipefail

duration_s=${1:-600}
build_dir=${2:-build}
out_dir=${3:-out/rig-soak}
emulator="$build_dir/bin/clearshape-rig-emulator"
soak="$build_dir/bench/rig_soak"
for exe in "$emulator" "$soak"; do
  [[ -x "$exe" ]] || { echo "rig-soak.sh: $exe is missing; build the targets clearshape_rig_emulator and rig_soak" >&2; exit 2; }
done
command -v cyclictest >/dev/null || { echo "rig-soak.sh: cyclictest is missing (apt-get install rt-tests)" >&2; exit 2; }
[[ "$duration_s" =~ ^[0-9]+$ && "$duration_s" -ge 10 ]] || { echo "rig-soak.sh: DURATION_S: a whole number of seconds >= 10, got '$duration_s'" >&2; exit 2; }
mkdir -p "$out_dir"

emulator_pid=""
cleanup() { [[ -n "$emulator_pid" ]] && kill "$emulator_pid" 2>/dev/null || true; }
trap cleanup EXIT

# cyclictest for the same window as a runner (started in this shell, so that `wait` finds it);
# its histogram goes to $1.
cyclictest_args=(-m -p 80 -i 1000 -D "${duration_s}" -q -h 20000)

# 1. The runner over the board in the emulator (real-time pacing, gyro noise on).
"$emulator" --seed 1 >"$out_dir/emulator.stdout" 2>"$out_dir/emulator.stderr" &
emulator_pid=$!
for _ in $(seq 100); do [[ -s "$out_dir/emulator.stdout" ]] && break; sleep 0.1; done
pty=$(head -n1 "$out_dir/emulator.stdout")
[[ -n "$pty" ]] || { echo "rig-soak.sh: the emulator printed no pty (see $out_dir/emulator.stderr)" >&2; exit 1; }
echo "rig-soak.sh: runner over the emulator ($pty) for ${duration_s} s" >&2
cyclictest "${cyclictest_args[@]}" --histfile="$out_dir/cyclictest-emulator.hist" >/dev/null 2>&1 &
cyc=$!
"$soak" --rig "serial:$pty" --duration-s "$duration_s" >"$out_dir/runner-emulator.json" || true
wait "$cyc" || true
kill "$emulator_pid"; wait "$emulator_pid" 2>/dev/null || true; emulator_pid=""

# 2. The runner over SimRig.
echo "rig-soak.sh: runner over SimRig for ${duration_s} s" >&2
cyclictest "${cyclictest_args[@]}" --histfile="$out_dir/cyclictest-sim.hist" >/dev/null 2>&1 &
cyc=$!
"$soak" --rig sim --duration-s "$duration_s" >"$out_dir/runner-sim.json" || true
wait "$cyc" || true

python3 - "$out_dir" "$duration_s" <<'PY'
import json, sys, pathlib
out, duration = pathlib.Path(sys.argv[1]), sys.argv[2]

def hist(path):
    counts, total, overflow = [], 0, 0
    for line in open(path):
        if line.startswith("# Histogram Overflows:"):
            overflow = int(line.split(":")[1].split()[0])
        if line.startswith("#") or not line.strip():
            continue
        us, n = line.split()[:2]
        counts.append((int(us), int(n)))
        total += int(n)
    total += overflow
    def pct(q):  # smallest latency with at least q of the samples at or below it
        acc = 0
        for us, n in counts:
            acc += n
            if acc >= q * total:
                return us
        return float("inf")
    mx = max((us for us, n in counts if n > 0), default=0)
    return total, pct(0.5), pct(0.99), (">20000" if overflow else mx)

rows = []
for name, label in (("emulator", "board in the emulator (SerialRig)"), ("sim", "SimRig")):
    r = json.load(open(out / f"runner-{name}.json"))
    n, p50, p99, mx = hist(out / f"cyclictest-{name}.hist")
    rows.append((label, r, (n, p50, p99, mx)))
print(f"Soak: {duration} s per rig at 1 kHz.\n")
print("| rig | cycles | lost | corrupted | overruns | runner latency p50 / p99 / max (µs) | SCHED_FIFO | cyclictest cycles | cyclictest p50 / p99 / max (µs) |")
print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
for label, r, (n, p50, p99, mx) in rows:
    print(f"| {label} | {r['cycles']} | {r['samples_lost']} | {r['frames_corrupted']} | {r['overruns']} | "
          f"{r['latency_p50_us']:.0f} / {r['latency_p99_us']:.0f} / {r['latency_max_us']:.0f} | "
          f"{'yes' if r['sched_fifo'] else 'no'} | {n} | {p50} / {p99} / {mx} |")
for label, r, _ in rows:
    if "board" in r:
        print(f"\n{label}: board {json.dumps(r['board'])}; link {json.dumps(r['link'])}")
PY
grep -o '[0-9.]* simulated s per wall s' "$out_dir/emulator.stderr" >&2 || true
