#!/usr/bin/env bash
# `cpack -G DEB` (docs/package.md): builds the .deb from the build tree and checks with dpkg-deb
# that it holds the CLI, the CMake package, the pkg-config file, the headers, the libraries and
# the Python module, and that it depends on the -dev packages find_dependency() needs and on the
# shared libraries the CLI loads (dpkg-shlibdeps) but not on the build host's BLAS (libatlas3-base);
# that it recommends/suggests what the Python package imports only when used; that it carries
# a machine-readable copyright file (DEB-5) with LICENSE's text, a man page generated from the
# CLI's --help that `man -l` renders without warnings, the Python package metadata, and a
# maintainer other than clearshape@localhost.
# Usage: deb_test.sh BUILD_DIR
set -euo pipefail
build=$1
work=$(mktemp -d "${TMPDIR:-/tmp}/clearshape-deb-test.XXXXXX")
trap 'rm -rf "$work"' EXIT
(cd "$build" && cpack -G DEB -B "$work" > "$work/cpack.log" 2>&1) || { cat "$work/cpack.log" >&2; exit 1; }
deb=$(ls "$work"/clearshape_*_amd64.deb)
dpkg-deb -c "$deb" > "$work/contents.txt"
for f in ./usr/bin/clearshape ./usr/lib/cmake/clearshape/clearshapeConfig.cmake \
         ./usr/lib/cmake/clearshape/clearshapeConfigVersion.cmake ./usr/lib/pkgconfig/clearshape.pc \
         ./usr/include/clearshape/shaping/design.hpp ./usr/lib/libclearshape_shaping.a \
         ./usr/lib/python3/dist-packages/clearshape/__init__.py \
         ./usr/lib/python3/dist-packages/clearshape/__init__.pyi ./usr/lib/python3/dist-packages/clearshape/py.typed; do
  grep -q " $f\$" "$work/contents.txt" || { echo "deb_test: $f missing from $deb" >&2; cat "$work/contents.txt" >&2; exit 1; }
done
grep -q "./usr/lib/python3/dist-packages/clearshape/_core" "$work/contents.txt" \
  || { echo "deb_test: the Python extension is missing" >&2; exit 1; }
depends=$(dpkg-deb -f "$deb" Depends)
for d in libceres-dev libsundials-dev libnlopt-cxx-dev libtomlplusplus-dev python3-numpy libc6 libstdc++6; do
  [[ "$depends" == *"$d"* ]] || { echo "deb_test: Depends lacks $d: $depends" >&2; exit 1; }
done
[[ $(dpkg-deb -f "$deb" Package) == clearshape ]]
fail() { echo "deb_test: $*" >&2; exit 1; }
version=$(dpkg-deb -f "$deb" Version)
source=$(sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$build/CMakeCache.txt")

# No build-host BLAS: neither in Depends nor NEEDED by anything the package ships.
[[ "$depends" != *atlas* ]] || fail "Depends names ATLAS (the build host's BLAS): $depends"
dpkg-deb -x "$deb" "$work/root"
for f in "$work/root/usr/bin/clearshape" "$work/root"/usr/lib/python3/dist-packages/clearshape/_core*.so; do
  ! objdump -p "$f" | grep -E "NEEDED +lib(f77blas|atlas|cblas)\." || fail "$f links ATLAS's own libraries"
done

# What the Python package imports only when it is used (bindings/python/clearshape).
recommends=$(dpkg-deb -f "$deb" Recommends) suggests=$(dpkg-deb -f "$deb" Suggests)
for d in python3-h5py python3-matplotlib; do
  [[ ", $recommends," == *", $d,"* ]] || fail "Recommends lacks $d: '$recommends'"
done
[[ ", $suggests," == *", python3-distributed,"* ]] || fail "Suggests lacks python3-distributed: '$suggests'"

maintainer=$(dpkg-deb -f "$deb" Maintainer)
[[ $maintainer =~ ^[^\<]+\ \<[^@\ ]+@[^@\ \>]+\>$ && $maintainer != *@localhost* ]] \
  || fail "Maintainer is '$maintainer'; want 'Name <address>', not @localhost"

# copyright: DEB-5 header, the Expat licence, and LICENSE's text word for word.
copyright=$work/root/usr/share/doc/clearshape/copyright
[[ -f $copyright ]] || fail "/usr/share/doc/clearshape/copyright missing"
[[ $(head -n 1 "$copyright") == "Format: https://www.debian.org/doc/packaging-manuals/copyright-format/1.0/" ]] \
  || fail "copyright has no DEB-5 Format line: $(head -n 1 "$copyright")"
grep -qx "Upstream-Name: clearshape" "$copyright" || fail "copyright lacks Upstream-Name"
grep -qx "Files: \*" "$copyright" || fail "copyright lacks a 'Files: *' paragraph"
holder=$(sed -n 's/^Copyright (c) //p' "$source/LICENSE")
grep -qx "Copyright: $holder" "$copyright" || fail "copyright lacks 'Copyright: $holder'"
[[ $(head -n 1 "$source/LICENSE") == "MIT License" && $(grep -c "^License: Expat$" "$copyright") == 2 ]] \
  || fail "copyright does not name LICENSE's MIT licence as Expat (Files paragraph and text)"
awk '/^License: Expat$/ {n = NR} {l[NR] = $0} END {for (i = n + 1; i <= NR; i++) print l[i]}' "$copyright" \
  | sed 's/^ //; s/^\.$//' > "$work/license_text"
tail -n +5 "$source/LICENSE" | sed -e :a -e '/^\n*$/{$d;N;ba' -e '}' > "$work/license_expected"
diff "$work/license_expected" "$work/license_text" >&2 || fail "copyright's licence text differs from LICENSE"

# The man page: generated from --help (every subcommand listed there is in it), renders cleanly.
man1=$work/root/usr/share/man/man1/clearshape.1.gz
[[ -f $man1 ]] || fail "/usr/share/man/man1/clearshape.1.gz missing (help2man: scripts/install-deps.sh)"
MANWIDTH=100 man --warnings -l "$man1" > "$work/man.txt" 2> "$work/man.err" || fail "man -l failed: $(cat "$work/man.err")"
[[ ! -s $work/man.err ]] || fail "man -l warns: $(cat "$work/man.err")"
grep -q "^NAME" "$work/man.txt" && grep -q "clearshape - " "$work/man.txt" || fail "man page lacks NAME: $(head "$work/man.txt")"
! grep -q "$build" <(zcat "$man1") || fail "the man page names the build directory"
subcommands=$("$build/bin/clearshape" --help | sed -n '/^Subcommands:/,$p' | awk 'NR > 1 && NF {print $1}')
[[ -n $subcommands ]] || fail "clearshape --help lists no subcommands"
for c in $subcommands; do
  grep -qE "^ +$c( |$)" "$work/man.txt" || fail "man page lacks subcommand $c"
done
grep -q "clearshape $version" <(zcat "$man1") || fail "man page lacks the version $version"

# Python package metadata beside the package.
metadata=$work/root/usr/lib/python3/dist-packages/clearshape-$version.dist-info/METADATA
[[ -f $metadata ]] || fail "clearshape-$version.dist-info/METADATA missing"
grep -qx "Name: clearshape" "$metadata" && grep -qx "Version: $version" "$metadata" || fail "METADATA: $(cat "$metadata")"
echo "deb_test: ok — $(basename "$deb"), $(wc -l < "$work/contents.txt") entries; Depends: $depends; Recommends: $recommends; Suggests: $suggests; Maintainer: $maintainer"
