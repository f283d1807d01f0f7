#!/usr/bin/env bash
# `cpack -G DEB` (docs/package.md): builds the four .debs from the build tree — clearshape (the
# CLI), libclearshape<M>.<m> (the shared library: SONAME, shlibs, ldconfig trigger),
# libclearshape-dev (headers, static libraries, CMake and pkg-config files) and
# python3-clearshape — and checks with dpkg-deb that each holds its files and no file is in two;
# that -dev and python3- depend on the same version of clearshape, -dev on the -dev packages
# find_dependency() needs, each on the shared libraries it loads (dpkg-shlibdeps) but not on the
# build host's BLAS (libatlas3-base), and clearshape on no -dev or Python package; that
# python3-clearshape recommends/suggests what it imports only when used; that each carries an
# extended description, a changelog.Debian.gz of this version and a machine-readable copyright
# file (DEB-5) with LICENSE's text; a man page generated from the CLI's --help that `man -l`
# renders without warnings, the Python package metadata, a maintainer other than
# clearshape@localhost; and that lintian reports no error on any of them.
# Usage: deb_test.sh BUILD_DIR
set -euo pipefail
build=$1
work=$(mktemp -d "${TMPDIR:-/tmp}/clearshape-deb-test.XXXXXX")
trap 'rm -rf "$work"' EXIT
(cd "$build" && cpack -G DEB -B "$work" > "$work/cpack.log" 2>&1) || { cat "$work/cpack.log" >&2; exit 1; }
fail() { echo "deb_test: $*" >&2; exit 1; }
source=$(sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$build/CMakeCache.txt")
upstream=$(sed -n 's/^CMAKE_PROJECT_VERSION:STATIC=//p' "$build/CMakeCache.txt")
version=$upstream-1
# The Debian split: exactly these four packages, each with its own files and no file twice. The
# shared library's package is named after its SONAME libclearshape.so.<major>.<minor>.
libpkg=libclearshape$(cut -d. -f1,2 <<< "$upstream")
packages=(clearshape "$libpkg" libclearshape-dev python3-clearshape)
declare -A deb
for p in "${packages[@]}"; do
  deb[$p]=$work/${p}_${version}_amd64.deb
  [[ -f ${deb[$p]} ]] || fail "cpack made no ${p}_${version}_amd64.deb: $(ls "$work")"
  [[ $(dpkg-deb -f "${deb[$p]}" Package) == "$p" && $(dpkg-deb -f "${deb[$p]}" Version) == "$version" ]] \
    || fail "${deb[$p]}: Package/Version $(dpkg-deb -f "${deb[$p]}" Package Version)"
  dpkg-deb -c "${deb[$p]}" > "$work/$p.contents"
  dpkg-deb -x "${deb[$p]}" "$work/root"
done
[[ $(ls "$work"/*.deb | wc -l) == 4 ]] || fail "more than the four packages: $(ls "$work"/*.deb)"
dups=$(cat "$work"/*.contents | awk '$1 ~ /^l/ {print $(NF - 2)} $1 ~ /^-/ {print $NF}' | sort | uniq -d)
[[ -z $dups ]] || fail "files in more than one package (dpkg would refuse them): $dups"
field() { dpkg-deb -f "${deb[$1]}" "$2"; }
has() {  # has PACKAGE FILE...: each file is in that package
  local p=$1; shift
  for f in "$@"; do grep -q " $f\$" "$work/$p.contents" || fail "$f missing from $p: $(cat "$work/$p.contents")"; done
}
has clearshape ./usr/bin/clearshape ./usr/share/man/man1/clearshape.1.gz
soname=${libpkg/libclearshape/libclearshape.so.}
has "$libpkg" "./usr/lib/$soname.${upstream##*.}" "./usr/lib/$soname -> $soname.${upstream##*.}"
has libclearshape-dev "./usr/lib/libclearshape.so -> $soname"
[[ $(objdump -p "$work/root/usr/lib/$soname.${upstream##*.}" | awk '$1 == "SONAME" {print $2}') == "$soname" ]] \
  || fail "the shared library's SONAME is not $soname"
[[ $(dpkg-deb -I "${deb[$libpkg]}" shlibs) == "libclearshape ${soname#libclearshape.so.} $libpkg (= $version)" ]] \
  || fail "$libpkg: shlibs is '$(dpkg-deb -I "${deb[$libpkg]}" shlibs 2>&1)'"
[[ $(dpkg-deb -I "${deb[$libpkg]}" triggers) == "activate-noawait ldconfig" ]] || fail "$libpkg: no ldconfig trigger"
[[ $(field "$libpkg" Section) == libs && $(field "$libpkg" Depends) == *libstdc++6* ]] \
  || fail "$libpkg: Section $(field "$libpkg" Section), Depends $(field "$libpkg" Depends)"
has libclearshape-dev ./usr/lib/cmake/clearshape/clearshapeConfig.cmake ./usr/lib/cmake/clearshape/clearshapeConfigVersion.cmake \
    ./usr/lib/pkgconfig/clearshape.pc ./usr/include/clearshape/shaping/design.hpp ./usr/lib/libclearshape_shaping.a
has python3-clearshape ./usr/lib/python3/dist-packages/clearshape/__init__.py \
    ./usr/lib/python3/dist-packages/clearshape/__init__.pyi ./usr/lib/python3/dist-packages/clearshape/py.typed
grep -q "./usr/lib/python3/dist-packages/clearshape/_core" "$work/python3-clearshape.contents" \
  || fail "the Python extension is missing from python3-clearshape"
! grep -qE "usr/(include|lib/cmake|lib/python3)/" "$work/clearshape.contents" || fail "clearshape ships -dev or Python files"

# Depends: the -dev and python3- packages need the same version of the CLI's package; the CLI's
# package needs only shared libraries (dpkg-shlibdeps), no -dev package, no Python.
for d in libc6 libstdc++6; do
  [[ $(field clearshape Depends) == *"$d"* ]] || fail "clearshape Depends lacks $d: $(field clearshape Depends)"
done
[[ $(field clearshape Depends) != *-dev* && $(field clearshape Depends) != *python3* ]] \
  || fail "clearshape depends on -dev or Python packages: $(field clearshape Depends)"
for d in "clearshape (= $version)" "$libpkg (= $version)" libceres-dev libsundials-dev libnlopt-cxx-dev libtomlplusplus-dev; do
  [[ ", $(field libclearshape-dev Depends)," == *", $d,"* ]] || fail "libclearshape-dev Depends lacks $d: $(field libclearshape-dev Depends)"
done
py=$(/usr/bin/python3 -c 'import sys; print(sys.version_info[0], sys.version_info[1])')
read -r py_major py_minor <<< "$py"
for d in "clearshape (= $version)" "python3 (>= $py_major.$py_minor~)" "python3 (<< $py_major.$((py_minor + 1)))" python3-numpy libstdc++6; do
  [[ $(field python3-clearshape Depends) == *"$d"* ]] || fail "python3-clearshape Depends lacks $d: $(field python3-clearshape Depends)"
done
[[ $(field clearshape Suggests) == python3-clearshape ]] || fail "clearshape Suggests '$(field clearshape Suggests)'"

# No build-host BLAS: neither in Depends nor NEEDED by anything the packages ship.
for p in "${packages[@]}"; do
  [[ $(field "$p" Depends) != *atlas* ]] || fail "$p Depends names ATLAS (the build host's BLAS): $(field "$p" Depends)"
done
for f in "$work/root/usr/bin/clearshape" "$work/root"/usr/lib/python3/dist-packages/clearshape/_core*.so; do
  ! objdump -p "$f" | grep -E "NEEDED +lib(f77blas|atlas|cblas)\." || fail "$f links ATLAS's own libraries"
done

# What the Python package imports only when it is used (bindings/python/clearshape).
recommends=$(field python3-clearshape Recommends) suggests=$(field python3-clearshape Suggests)
for d in python3-h5py python3-matplotlib; do
  [[ ", $recommends," == *", $d,"* ]] || fail "python3-clearshape Recommends lacks $d: '$recommends'"
done
[[ ", $suggests," == *", python3-distributed,"* ]] || fail "python3-clearshape Suggests lacks python3-distributed: '$suggests'"

for p in "${packages[@]}"; do
  maintainer=$(field "$p" Maintainer)
  [[ $maintainer =~ ^[^\<]+\ \<[^@\ ]+@[^@\ \>]+\>$ && $maintainer != *@localhost* ]] \
    || fail "$p: Maintainer is '$maintainer'; want 'Name <address>', not @localhost"
  # An extended description (lintian: extended-description-is-empty), its own summary line.
  [[ $(field "$p" Description | wc -l) -ge 3 ]] || fail "$p: no extended description: $(field "$p" Description)"
  # changelog.Debian.gz: this version, parsed by dpkg's own parser.
  changelog=$work/root/usr/share/doc/$p/changelog.Debian.gz
  [[ -f $changelog ]] || fail "/usr/share/doc/$p/changelog.Debian.gz missing"
  zcat "$changelog" > "$work/changelog"
  [[ $(dpkg-parsechangelog -l "$work/changelog" -S Version) == "$version" ]] || fail "$p: changelog: $(cat "$work/changelog")"
  [[ $(dpkg-parsechangelog -l "$work/changelog" -S Maintainer) == "$maintainer" ]] || fail "$p: changelog maintainer"
  cmp -s "$work/root/usr/share/doc/$p/copyright" "$work/root/usr/share/doc/clearshape/copyright" \
    || fail "/usr/share/doc/$p/copyright missing or not the same as clearshape's"
done

# lintian (Debian's package checker): no error (E:) on any of the four; the warnings left are
# listed in docs/package.md.
command -v lintian > /dev/null || fail "lintian not installed (scripts/install-deps.sh installs it)"
rc=0; lintian --fail-on error --tag-display-limit 0 "${deb[@]}" > "$work/lintian.txt" 2>&1 || rc=$?
! grep -E "^E: " "$work/lintian.txt" >&2 || fail "lintian reports errors (above)"
[[ $rc == 0 ]] || fail "lintian failed (exit $rc): $(cat "$work/lintian.txt")"
lintian_warnings=$(grep -c "^W: " "$work/lintian.txt" || true)

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
grep -q "clearshape $upstream" <(zcat "$man1") || fail "man page lacks the version $upstream"

# Python package metadata beside the package.
metadata=$work/root/usr/lib/python3/dist-packages/clearshape-$upstream.dist-info/METADATA
[[ -f $metadata ]] || fail "clearshape-$upstream.dist-info/METADATA missing"
grep -qx "Name: clearshape" "$metadata" && grep -qx "Version: $upstream" "$metadata" || fail "METADATA: $(cat "$metadata")"
echo "deb_test: ok — ${packages[*]} $version; python3-clearshape Recommends: $recommends; Suggests: $suggests; Maintainer: $maintainer; lintian: 0 errors, $lintian_warnings warnings"
