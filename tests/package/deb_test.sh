#!/usr/bin/env bash
# `cpack -G DEB` (docs/package.md): builds the .deb from the build tree and checks with dpkg-deb
# that it holds the CLI, the CMake package, the pkg-config file, the headers, the libraries and
# the Python module, and that it depends on the -dev packages find_dependency() needs and on the
# shared libraries the CLI loads (dpkg-shlibdeps).
# Usage: deb_test.sh BUILD_DIR
set -euo pipefail
build=$1
work=$(mktemp -d /tmp/clearshape-deb-test.XXXXXX)
trap 'rm -rf "$work"' EXIT
(cd "$build" && cpack -G DEB -B "$work" > "$work/cpack.log" 2>&1) || { cat "$work/cpack.log" >&2; exit 1; }
deb=$(ls "$work"/clearshape_*_amd64.deb)
dpkg-deb -c "$deb" > "$work/contents.txt"
for f in ./usr/bin/clearshape ./usr/lib/cmake/clearshape/clearshapeConfig.cmake \
         ./usr/lib/cmake/clearshape/clearshapeConfigVersion.cmake ./usr/lib/pkgconfig/clearshape.pc \
         ./usr/include/clearshape/shaping/design.hpp ./usr/lib/libclearshape_shaping.a \
         ./usr/lib/python3/dist-packages/clearshape/__init__.py; do
  grep -q " $f\$" "$work/contents.txt" || { echo "deb_test: $f missing from $deb" >&2; cat "$work/contents.txt" >&2; exit 1; }
done
grep -q "./usr/lib/python3/dist-packages/clearshape/_core" "$work/contents.txt" \
  || { echo "deb_test: the Python extension is missing" >&2; exit 1; }
depends=$(dpkg-deb -f "$deb" Depends)
for d in libceres-dev libsundials-dev libnlopt-cxx-dev libtomlplusplus-dev python3-numpy libc6 libstdc++6; do
  [[ "$depends" == *"$d"* ]] || { echo "deb_test: Depends lacks $d: $depends" >&2; exit 1; }
done
[[ $(dpkg-deb -f "$deb" Package) == clearshape ]]
echo "deb_test: ok — $(basename "$deb"), $(wc -l < "$work/contents.txt") entries; Depends: $depends"
