#!/usr/bin/env bash
# The Debian packages and the wheel on a clean Debian 12 root (docs/package.md, "A clean Debian 12
# root"): builds the four .debs from BUILD_DIR with cpack and the wheel with `python3 -m build`, makes
# a minimal bookworm root with debootstrap, and there follows three users through the docs, running
# the docs' own code blocks (scripts/doc-block.py), so the test fails when the docs drift:
#   1. a Python user in a venv (docs/python.md, "A wheel for a venv", then "A session" and the
#      "Errors" example, and a `recommend`): the docs' apt line (the CLI package alone, for the
#      libraries the extension loads), venv, pip install of the wheel, the examples in the venv;
#   2. a C++ user (docs/package.md): the docs' apt lines, the CLI (--version, a design, the man page),
#      tests/package/consumer (CMake find_package as the docs show it, no C++ standard set) building
#      examples/02_design_shapers.cpp (it checks its own results) against the static modules and
#      against clearshape::shared, the docs' pkg-config line; `import clearshape` from the .deb;
#   3. a cluster user (docs/sweeps.md): the docs' cluster block (apt, a dask-scheduler, two
#      dask-workers, in the root), the docs' sweep file and `clearshape sweep … --scheduler`, whose
#      results must equal the local engine's byte for byte.
# Needs root (debootstrap, chroot, mount) and the network (deb.debian.org), so it is not part of
# `make test`: `make test-clean-root` runs it. Takes a few minutes, mostly downloads. Every process
# started in the root is killed and every mount undone on exit, also on failure.
# Usage: scripts/test-clean-root.sh [BUILD_DIR]    (default build; MIRROR=… to use another mirror)
set -euo pipefail
source_dir=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-$source_dir/build}" && pwd)
mirror=${MIRROR:-http://deb.debian.org/debian}
fail() { echo "test-clean-root: $*" >&2; exit 1; }
[[ $(id -u) == 0 ]] || fail "needs root (debootstrap, chroot)"
for tool in debootstrap cpack chroot flock /usr/bin/python3; do
  command -v "$tool" > /dev/null || fail "$tool not found (Debian: apt install debootstrap cmake util-linux python3)"
done
[[ -x $build/bin/clearshape ]] || fail "$build/bin/clearshape not built (make build, or cmake --build $build)"

/usr/bin/python3 -c "import build, wheel" 2> /dev/null || fail "/usr/bin/python3 lacks build or wheel (Debian: python3-build python3-wheel)"

work=$(mktemp -d "${TMPDIR:-/tmp}/clearshape-clean-root.XXXXXX")
root=$work/root
in_root_pids() {  # every process whose root directory is the clean root (chroot), by id
  local p
  for p in /proc/[0-9]*; do
    [[ $(readlink "$p/root" 2> /dev/null) == "$root" ]] && echo "${p#/proc/}"
  done
  return 0
}
cleanup() {
  local pids
  pids=$(in_root_pids)
  if [[ -n $pids ]]; then
    kill $pids 2> /dev/null || true
    sleep 2
    pids=$(in_root_pids)
    [[ -z $pids ]] || kill -9 $pids 2> /dev/null || true
  fi
  for m in "$root/dev/shm" "$root/dev/pts" "$root/dev" "$root/proc"; do
    mountpoint -q "$m" 2> /dev/null && umount -l "$m"
  done
  rm -rf "$work"
}
trap cleanup EXIT
trap 'exit 130' INT TERM HUP
step() { echo "test-clean-root: [$((SECONDS))s] $*"; }
doc() { /usr/bin/python3 "$source_dir/scripts/doc-block.py" "$source_dir/docs/$1" "${@:2}"; }
commands() { grep -v '^#' | sed -e 's/ *#.*$//' -e '/^ *$/d'; }  # a block's commands, comments dropped
# The build tree is shared: cpack runs the install (and its build of what is out of date) under the lock.
step "cpack -G DEB and the wheel (docs/python.md's command) from $build"
(cd "$build" && flock /tmp/clearshape-build.lock cpack -G DEB -B "$work/debs" > "$work/cpack.log" 2>&1) \
  || { cat "$work/cpack.log" >&2; exit 1; }
debs=("$work"/debs/*.deb)
[[ ${#debs[@]} == 4 ]] || fail "want four .debs, cpack made: ${debs[*]}"
mkdir -p "$work/host" && ln -s "$build" "$work/host/build"
wheel_build=$(doc python.md "A wheel for a venv" sh | commands | grep -- '-m build')
(cd "$work/host" && flock /tmp/clearshape-build.lock sh -c "$wheel_build" > "$work/wheel.log" 2>&1) \
  || { cat "$work/wheel.log" >&2; fail "the docs' wheel command failed: $wheel_build"; }
ls "$work/host/dist"

step "debootstrap bookworm (minbase) from $mirror"
debootstrap --variant=minbase bookworm "$root" "$mirror" > "$work/debootstrap.log" 2>&1 \
  || { tail -n 30 "$work/debootstrap.log" >&2; fail "debootstrap failed"; }
mount -t proc proc "$root/proc"
mount --bind /dev "$root/dev"
mount --bind /dev/pts "$root/dev/pts"
mount -t tmpfs -o size=256m shm "$root/dev/shm"  # the root's own: multiprocessing's semaphores (sweeps, Dask)
cp /etc/resolv.conf "$root/etc/resolv.conf"
# `apt install` as the docs write it, without its question (a user answers yes)
echo 'APT::Get::Assume-Yes "true";' > "$root/etc/apt/apt.conf.d/90test-clean-root"
in_root() { chroot "$root" /usr/bin/env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root LANG=C.UTF-8 \
  DEBIAN_FRONTEND=noninteractive "$@"; }
user_dir=/srv/user  # the user's folder: build/ holds the .debs, dist/ the wheel, as in the docs
mkdir -p "$root$user_dir/build" "$root$user_dir/dist" "$root/srv/consumer"
cp "${debs[@]}" "$root$user_dir/build/"
cp "$work"/host/dist/*.whl "$root$user_dir/dist/"
cp "$source_dir/tests/package/consumer/CMakeLists.txt" "$source_dir/examples/02_design_shapers.cpp" "$root/srv/consumer/"
as_user() {  # one of the docs' command lines, as written (sudo dropped: we are root), in the user's folder
  in_root sh -c "cd $user_dir && ${1#sudo }" >> "$work/user.log" 2>&1 || { tail -n 40 "$work/user.log" >&2; fail "failed: $1"; }
}
in_root apt-get update -q > "$work/apt.log" 2>&1 || { cat "$work/apt.log" >&2; fail "apt-get update failed"; }
count() { in_root dpkg-query -W -f '${db:Status-Abbrev}\n' | grep -c '^ii'; }
apt_install() { in_root apt-get install -y -q "$@" >> "$work/apt.log" 2>&1 \
  || { tail -n 40 "$work/apt.log" >&2; fail "apt-get install $* failed"; }; }
installs=$(doc package.md "What is installed" sh | sed -e ':a' -e '/\\$/N; s/\\\n */ /; ta' | grep '^sudo apt install')
[[ $(wc -l <<< "$installs") == 2 ]] || fail "docs/package.md: want two 'sudo apt install' lines, got: $installs"
before=$(count)

step "1. Python user in a venv (docs/python.md, \"A wheel for a venv\"), the CLI package alone from the .debs"
as_user "$(head -n 1 <<< "$installs")"  # docs/package.md: the CLI alone: what it pulls
cli=$(count)
venv_block=$(doc python.md "A wheel for a venv" sh | commands | sed -n '/^sudo apt install/,$p')
[[ -n $venv_block ]] || fail "docs/python.md: no 'sudo apt install' line after the wheel's build"
while IFS= read -r line; do
  as_user "$line"
done <<< "$venv_block"
python_version=$(in_root sh -c "cd $user_dir && venv/bin/python -c \"import importlib.metadata as md; print(md.version('clearshape'))\"")
deb_version=$(dpkg-deb -f "$work"/debs/clearshape_*.deb Version | sed 's/-[^-]*$//')
[[ $python_version == "$deb_version" ]] || fail "importlib.metadata.version in the venv says '$python_version'"
doc python.md "A session" python > "$root$user_dir/session.py"
doc python.md "What is bound" python > "$root$user_dir/errors.py"
cat > "$root$user_dir/recommend.py" <<'PY'
# the session's unshaped run as a recording, then recommend on it (docs/recommend.md)
import numpy as np, clearshape as cs
assert cs.__file__.startswith("/srv/user/venv/lib/"), cs.__file__  # the wheel, not a system copy
t, u = cs.signal("step", amplitude=20, start_s=0.1, duration_s=3)
truth = cs.thesis_truth(); truth.clearance_rad = np.deg2rad(0.5)
run = cs.simulate(np.deg2rad(u), 1e-3, "position", truth, duration_s=3)
np.savetxt("run.csv", np.column_stack([t, np.rad2deg(run["link_rate_rad_s"])]), delimiter=",",
           header="time_s,rate_deg_s", comments="")
r = cs.recommend(["run.csv"], column="rate_deg_s", from_s=0.5)
assert r["recommendation"]["name"] in cs.shaper_methods(), r["recommendation"]
print("recommend:", r["recommendation"]["shape_command"])
PY
for example in session errors recommend; do
  in_root sh -c "cd $user_dir && venv/bin/python $example.py" 2>&1 | tee -a "$work/user.log" \
    || fail "docs/python.md's $example example failed in the venv"
done
[[ $(in_root dpkg-query -W -f '${db:Status-Abbrev}' python3-clearshape 2> /dev/null) != ii* ]] \
  || fail "python3-clearshape is installed: the venv must work without it"

step "2. C++ user (docs/package.md): the four packages, then g++, cmake (and man to read the page)"
as_user "$(tail -n 1 <<< "$installs")"
all=$(count)
apt_install g++ cmake make man-db
echo "test-clean-root: packages installed: $before in the root, +$((cli - before)) with clearshape (the CLI)," \
     "+$((all - cli)) with python3-venv, NumPy, the shared library, libclearshape-dev and python3-clearshape" \
     "(Recommends included), +$(($(count) - all)) for g++, cmake, man"
names=()
for d in "${debs[@]}"; do names+=("$(dpkg-deb -f "$d" Package)"); done
installed=$(in_root dpkg-query -W -f '${Package} ${Version} ${db:Status-Abbrev}\n' "${names[@]}")
echo "$installed"
[[ $(grep -c " ii *$" <<< "$installed") == 4 ]] || fail "not all four packages installed"

version=$(in_root clearshape --version)
[[ $version == "clearshape $deb_version" ]] || fail "clearshape --version says '$version'"
in_root clearshape shape --method zvd --frequency-hz 3.32 --zeta 0.288 > "$work/shape.txt" 2>&1 \
  || { cat "$work/shape.txt" >&2; fail "clearshape shape failed"; }
head -n 5 "$work/shape.txt"
in_root man -P cat clearshape 2> /dev/null | grep -q "^NAME" || fail "man clearshape shows no page"

# The consumer project uses the docs' CMake lines (my_tool being its target `consumer`).
while IFS= read -r line; do
  grep -qF "$(sed -e 's/my_tool/consumer/' -e 's/clearshape::clearshape/${CLEARSHAPE_TARGET}/' -e 's/ REQUIRED)/ REQUIRED CONFIG)/' <<< "$line")" \
    "$root/srv/consumer/CMakeLists.txt" || fail "tests/package/consumer does not do docs/package.md's: $line"
done < <(doc package.md "Using it from CMake" cmake | commands)
in_root cmake -S /srv/consumer -B /srv/consumer/build -DEXAMPLE_SOURCE=/srv/consumer/02_design_shapers.cpp \
  > "$work/consumer.log" 2>&1 || { cat "$work/consumer.log" >&2; fail "the consumer's cmake failed"; }
grep -q "clearshape_DIR = /usr/lib/cmake/clearshape" "$work/consumer.log" || fail "found no /usr clearshape: $(cat "$work/consumer.log")"
in_root cmake --build /srv/consumer/build > "$work/consumer-build.log" 2>&1 \
  || { cat "$work/consumer-build.log" >&2; fail "the consumer did not build"; }
in_root /srv/consumer/build/consumer | tail -n 2
in_root cmake -S /srv/consumer -B /srv/consumer/build-shared -DEXAMPLE_SOURCE=/srv/consumer/02_design_shapers.cpp \
  -DCLEARSHAPE_TARGET=clearshape::shared > "$work/consumer-shared.log" 2>&1 \
  || { cat "$work/consumer-shared.log" >&2; fail "the shared consumer's cmake failed"; }
in_root cmake --build /srv/consumer/build-shared > "$work/consumer-shared-build.log" 2>&1 \
  || { cat "$work/consumer-shared-build.log" >&2; fail "the shared consumer did not build"; }
in_root ldd /srv/consumer/build-shared/consumer | grep "libclearshape.so" || fail "the shared consumer does not load libclearshape"
in_root /srv/consumer/build-shared/consumer > /dev/null || fail "the shared consumer failed"
cp "$source_dir/examples/02_design_shapers.cpp" "$root$user_dir/my_tool.cpp"
pc_line=$(doc package.md "Using it with pkg-config" sh | commands)
as_user "$pc_line -o my_tool"
in_root "$user_dir/my_tool" > /dev/null || fail "the pkg-config consumer ($pc_line) failed"
in_root sh -c "cd / && python3 -c \"
import importlib.metadata as md, clearshape
s = clearshape.design('zvd', frequency_hz=3.32, zeta=0.288)
assert abs(clearshape.residual_vibration(s, 3.32, 0.288)) < 1e-12
assert clearshape.__file__.startswith('/usr/lib/python3/dist-packages/'), clearshape.__file__
assert md.version('clearshape') == clearshape.__version__
print('python3:', clearshape.__file__, s, 'metadata version', md.version('clearshape'))
\"" || fail "import clearshape from python3-clearshape failed"

step "3. cluster user (docs/sweeps.md): the docs' cluster block, a dask-scheduler and two dask-workers in the root"
port=$(/usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
cluster=$(doc sweeps.md "Sweeps: many simulated runs, on one machine or a Dask cluster" sh 2 | commands \
  | sed -e "s|tcp://head:8786|tcp://127.0.0.1:$port|g" -e "s|--port 8786|--port $port|g")
address=tcp://127.0.0.1:$port
grep -q '^dask-scheduler ' <<< "$cluster" && grep -q '^dask-worker ' <<< "$cluster" \
  || fail "docs/sweeps.md's cluster block starts no dask-scheduler and dask-worker: $cluster"
as_user "$(grep '^sudo apt install' <<< "$cluster")"
in_root sh -c "cd $user_dir && exec $(grep '^dask-scheduler ' <<< "$cluster")" > "$work/scheduler.log" 2>&1 &
for w in 1 2; do
  in_root sh -c "cd $user_dir && exec $(grep '^dask-worker ' <<< "$cluster")" > "$work/worker$w.log" 2>&1 &
done
in_root python3 -c "
from distributed import Client
with Client('$address', timeout=60) as c:
    c.wait_for_workers(2, timeout=120)
    print('test-clean-root: scheduler', '$address', 'has', len(c.scheduler_info()['workers']), 'workers')
" || { tail -n 20 "$work"/scheduler.log "$work"/worker*.log >&2; fail "no scheduler with two workers at $address"; }
mkdir -p "$root$user_dir/studies"
doc sweeps.md "The sweep file" toml > "$root$user_dir/studies/sweep-play.toml"
sweeps=$(doc sweeps.md "Sweeps: many simulated runs, on one machine or a Dask cluster" sh 1 | commands)
dask_sweep=$(grep -e '--scheduler' <<< "$sweeps" | sed "s|tcp://head:8786|$address|")
local_sweep=$(grep -ve '--scheduler' <<< "$sweeps")
[[ -n $dask_sweep && -n $local_sweep ]] || fail "docs/sweeps.md: want a local and a --scheduler sweep command: $sweeps"
out=$(sed -n 's/.*--out \([^ ]*\).*/\1/p' <<< "$local_sweep")
start=$SECONDS
as_user "$dask_sweep"
echo "test-clean-root: $dask_sweep: $((SECONDS - start)) s"
batches=$(find "$root$user_dir/$out/.sweep" -name 'batch-*.json' | wc -l)
in_root python3 -c "
from distributed import Client
with Client('$address', timeout=60) as c:
    done = c.run_on_scheduler(lambda dask_scheduler: sum(p.state_counts['memory'] for p in dask_scheduler.task_prefixes.values()))
assert done == $batches > 0, f'the scheduler finished {done} tasks, the sweep wrote $batches batches'
print('test-clean-root: the scheduler ran the sweep as', done, 'tasks, one per batch')
" || fail "the Dask sweep's batches did not run on the cluster"
as_user "mv $out $out-dask"
start=$SECONDS
as_user "$local_sweep"
echo "test-clean-root: $local_sweep: $((SECONDS - start)) s"
for f in results.h5 results.csv results.json improvement_map.png; do
  cmp "$root$user_dir/$out/$f" "$root$user_dir/$out-dask/$f" || fail "$out/$f: the Dask sweep's differs from the local one's"
done
points=$(($(wc -l < "$root$user_dir/$out/results.csv") - 1))
echo "test-clean-root: $points points, results.h5, .csv, .json and improvement_map.png byte-identical (Dask, local)"
count_failed='import csv, sys; print(sum(r["status"] != "ok" for r in csv.DictReader(open(sys.argv[1]))))'
failed=$(/usr/bin/python3 -c "$count_failed" "$root$user_dir/$out/results.csv")
[[ $points -gt 0 && $failed == 0 ]] || fail "$out/results.csv: $points points, $failed not ok"

step "ok: root of $(du -shx "$root" | cut -f1), $(count) packages"
