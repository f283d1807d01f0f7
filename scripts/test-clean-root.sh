#!/usr/bin/env bash
# The Debian packages on a clean Debian 12 root (docs/package.md, "A clean Debian 12 root"):
# builds the four .debs from BUILD_DIR with cpack, makes a minimal bookworm root with
# debootstrap, installs the packages there with apt (as a user would, Recommends included)
# together with g++ and cmake, and runs inside it:
#   1. the CLI: --version, a shaper design, the man page;
#   2. a C++ consumer: tests/package/consumer (CMake find_package, no C++ standard set) building
#      examples/02_design_shapers.cpp, which checks its own results, against the static modules
#      and against the shared library (clearshape::shared); and the example built with pkg-config;
#   3. Python: import clearshape, a design, importlib.metadata.version("clearshape").
# Needs root (debootstrap, chroot, mount) and the network (deb.debian.org), so it is not part of
# `make test`: `make test-clean-root` runs it. Takes a few minutes, mostly downloads.
# Usage: scripts/test-clean-root.sh [BUILD_DIR]    (default build; MIRROR=… to use another mirror)
set -euo pipefail
source_dir=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-$source_dir/build}" && pwd)
mirror=${MIRROR:-http://deb.debian.org/debian}
fail() { echo "test-clean-root: $*" >&2; exit 1; }
[[ $(id -u) == 0 ]] || fail "needs root (debootstrap, chroot)"
for tool in debootstrap cpack chroot; do
  command -v "$tool" > /dev/null || fail "$tool not found (Debian: apt install debootstrap cmake)"
done
[[ -x $build/bin/clearshape ]] || fail "$build/bin/clearshape not built (make build, or cmake --build $build)"

work=$(mktemp -d "${TMPDIR:-/tmp}/clearshape-clean-root.XXXXXX")
root=$work/root
cleanup() {
  for m in "$root/dev/pts" "$root/dev" "$root/proc"; do
    mountpoint -q "$m" 2> /dev/null && umount -l "$m"
  done
  rm -rf "$work"
}
trap cleanup EXIT
step() { echo "test-clean-root: [$((SECONDS))s] $*"; }

step "cpack -G DEB in $build"
(cd "$build" && cpack -G DEB -B "$work/debs" > "$work/cpack.log" 2>&1) || { cat "$work/cpack.log" >&2; exit 1; }
debs=("$work"/debs/*.deb)
[[ ${#debs[@]} == 4 ]] || fail "want four .debs, cpack made: ${debs[*]}"

step "debootstrap bookworm (minbase) from $mirror"
debootstrap --variant=minbase bookworm "$root" "$mirror" > "$work/debootstrap.log" 2>&1 \
  || { tail -n 30 "$work/debootstrap.log" >&2; fail "debootstrap failed"; }
mount -t proc proc "$root/proc"
mount --bind /dev "$root/dev"
mount --bind /dev/pts "$root/dev/pts"
cp /etc/resolv.conf "$root/etc/resolv.conf"
in_root() { chroot "$root" /usr/bin/env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root LANG=C.UTF-8 "$@"; }

step "apt install the four packages, g++, cmake (and man to read the page)"
mkdir -p "$root/srv/debs" "$root/srv/consumer"
cp "${debs[@]}" "$root/srv/debs/"
cp "$source_dir/tests/package/consumer/CMakeLists.txt" "$source_dir/examples/02_design_shapers.cpp" "$root/srv/consumer/"
in_root apt-get update -q > "$work/apt.log" 2>&1 || { cat "$work/apt.log" >&2; fail "apt-get update failed"; }
count() { in_root dpkg-query -W -f '${db:Status-Abbrev}\n' | grep -c '^ii'; }
apt_install() { in_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -q "$@" >> "$work/apt.log" 2>&1 \
  || { tail -n 40 "$work/apt.log" >&2; fail "apt-get install $* failed"; }; }
before=$(count)
apt_install "/srv/debs/$(basename "$work"/debs/clearshape_*.deb)"  # the CLI alone first: what it pulls
cli=$(count)
in_debs=()
for d in "${debs[@]}"; do in_debs+=("/srv/debs/$(basename "$d")"); done
apt_install "${in_debs[@]}"
all=$(count)
apt_install g++ cmake make man-db
echo "test-clean-root: packages installed: $before in the root, +$((cli - before)) with clearshape (the CLI)," \
     "+$((all - cli)) with the shared library, libclearshape-dev and python3-clearshape (Recommends included), +$(($(count) - all)) for g++, cmake, man"
names=()
for d in "${debs[@]}"; do names+=("$(dpkg-deb -f "$d" Package)"); done
installed=$(in_root dpkg-query -W -f '${Package} ${Version} ${db:Status-Abbrev}\n' "${names[@]}")
echo "$installed"
[[ $(grep -c " ii *$" <<< "$installed") == 4 ]] || fail "not all four packages installed"

step "1. the CLI"
version=$(in_root clearshape --version)
[[ $version == "clearshape $(dpkg-deb -f "$work"/debs/clearshape_*.deb Version | sed 's/-[^-]*$//')" ]] \
  || fail "clearshape --version says '$version'"
in_root clearshape shape --method zvd --frequency-hz 3.32 --zeta 0.288 > "$work/shape.txt" 2>&1 \
  || { cat "$work/shape.txt" >&2; fail "clearshape shape failed"; }
head -n 5 "$work/shape.txt"
in_root man -P cat clearshape 2> /dev/null | grep -q "^NAME" || fail "man clearshape shows no page"

step "2. C++ consumer: CMake find_package (no C++ standard set), then pkg-config"
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
in_root sh -c 'c++ -O1 /srv/consumer/02_design_shapers.cpp -o /srv/pc_consumer $(pkg-config --cflags --libs clearshape)' \
  || fail "the pkg-config consumer did not build"
in_root /srv/pc_consumer > /dev/null || fail "the pkg-config consumer failed"

step "3. Python: import clearshape"
in_root python3 -c "
import importlib.metadata as md, clearshape
s = clearshape.design('zvd', frequency_hz=3.32, zeta=0.288)
assert abs(clearshape.residual_vibration(s, 3.32, 0.288)) < 1e-12
assert clearshape.__file__.startswith('/usr/lib/python3/dist-packages/'), clearshape.__file__
assert md.version('clearshape') == clearshape.__version__
print('python3:', clearshape.__file__, s, 'metadata version', md.version('clearshape'))
" || fail "import clearshape failed"

step "ok: root of $(du -shx "$root" | cut -f1), $(count) packages"
