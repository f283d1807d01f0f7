#!/usr/bin/env bash
# The installed package (docs/package.md): `cmake --install` into a temporary prefix, then
#   1. a separate CMake project builds examples/02_design_shapers.cpp against the installed
#      clearshape::clearshape (find_package, nothing from the source or build tree) and runs it;
#      it sets no C++ standard: C++20 must come from the exported targets (cxx_std_20);
#      1b. the same against the shared library clearshape::shared (SONAME libclearshape.so.M.m);
#   2. the same example built with the installed pkg-config file only, and run;
#   3. the installed Python module imports from the prefix and designs a shaper, and its package
#      metadata answers importlib.metadata.version("clearshape") with the CLI's version.
# Usage: install_test.sh BUILD_DIR SOURCE_DIR PYTHON
set -euo pipefail
build=$1 source=$2 python=$3
work=$(mktemp -d "${TMPDIR:-/tmp}/clearshape-install-test.XXXXXX")
trap 'rm -rf "$work"' EXIT
prefix=$work/prefix
example=$source/examples/02_design_shapers.cpp

cmake --install "$build" --prefix "$prefix" > "$work/install.log"
for f in bin/clearshape lib/cmake/clearshape/clearshapeConfig.cmake \
         lib/cmake/clearshape/clearshapeConfigVersion.cmake lib/cmake/clearshape/clearshapeTargets.cmake \
         lib/pkgconfig/clearshape.pc lib/libclearshape_core.a lib/libclearshape_study.a \
         include/clearshape/shaping/design.hpp include/clearshape/core/version.hpp \
         share/doc/clearshape/copyright share/man/man1/clearshape.1.gz; do
  [[ -e $prefix/$f ]] || { echo "install_test: $f was not installed" >&2; exit 1; }
done
# The exported targets must not point back into the source or build tree.
if grep -l -e "$source" -e "$build" "$prefix"/lib/cmake/clearshape/*.cmake "$prefix/lib/pkgconfig/clearshape.pc"; then
  echo "install_test: an installed CMake/pkg-config file names the source or build tree" >&2
  exit 1
fi

# 1. CMake consumer.
cmake -S "$source/tests/package/consumer" -B "$work/consumer" -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_PREFIX_PATH="$prefix" -DEXAMPLE_SOURCE="$example" -DCMAKE_EXPORT_COMPILE_COMMANDS=ON \
      > "$work/consumer.log" 2>&1 \
  || { cat "$work/consumer.log" >&2; exit 1; }
grep -q "clearshape_DIR = $prefix/lib/cmake/clearshape" "$work/consumer.log" \
  || { echo "install_test: the consumer did not find the installed package" >&2; cat "$work/consumer.log" >&2; exit 1; }
# The consumer sets no standard, so a -std=…20 flag can only come from clearshape's targets.
grep -Eq -- '-std=(c|gnu)\+\+20' "$work/consumer/compile_commands.json" \
  || { echo "install_test: the installed targets do not require C++20 (cxx_std_20)" >&2; cat "$work/consumer.log" >&2; exit 1; }
cmake --build "$work/consumer" > "$work/consumer-build.log" 2>&1 || { cat "$work/consumer-build.log" >&2; exit 1; }
"$work/consumer/consumer"

# 1b. The same against the shared library clearshape::shared: it needs libclearshape.so.<M>.<m>
# (the SONAME) and runs from the prefix's lib; again no C++ standard set.
soname=$(objdump -p "$prefix"/lib/libclearshape.so | awk '$1 == "SONAME" {print $2}')
[[ $soname =~ ^libclearshape\.so\.[0-9]+\.[0-9]+$ && -f $prefix/lib/$soname ]] \
  || { echo "install_test: the shared library's SONAME is '$soname'" >&2; ls -l "$prefix/lib" >&2; exit 1; }
cmake -S "$source/tests/package/consumer" -B "$work/consumer-shared" -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_PREFIX_PATH="$prefix" -DEXAMPLE_SOURCE="$example" -DCLEARSHAPE_TARGET=clearshape::shared \
      -DCMAKE_EXPORT_COMPILE_COMMANDS=ON > "$work/consumer-shared.log" 2>&1 \
  || { cat "$work/consumer-shared.log" >&2; exit 1; }
grep -Eq -- '-std=(c|gnu)\+\+20' "$work/consumer-shared/compile_commands.json" \
  || { echo "install_test: clearshape::shared does not require C++20" >&2; exit 1; }
cmake --build "$work/consumer-shared" > "$work/consumer-shared-build.log" 2>&1 \
  || { cat "$work/consumer-shared-build.log" >&2; exit 1; }
objdump -p "$work/consumer-shared/consumer" | grep -q "NEEDED *$soname\$" \
  || { echo "install_test: the shared consumer does not load $soname" >&2; exit 1; }
objdump -t "$work/consumer-shared/consumer" | grep "clearshape7shaping.*design" > "$work/design-symbols"
[[ -s $work/design-symbols ]] && ! grep -qv "\*UND\*" "$work/design-symbols" \
  || { echo "install_test: the shared consumer has clearshape's design code linked in statically" >&2; exit 1; }
LD_LIBRARY_PATH="$prefix/lib" "$work/consumer-shared/consumer" > /dev/null

# 2. pkg-config consumer.
flags=$(PKG_CONFIG_PATH="$prefix/lib/pkgconfig" pkg-config --cflags --libs clearshape)
c++ -O1 "$example" -o "$work/pc_consumer" $flags
"$work/pc_consumer" > /dev/null

# 3. Python from the prefix (not the build tree); PYTHON "none" when the module is not built.
[[ $python == none ]] || PYTHONPATH="$prefix/lib/python3/dist-packages" "$python" -c "
import clearshape, sys
assert clearshape.__file__.startswith('$prefix'), clearshape.__file__
s = clearshape.design('zvd', frequency_hz=3.32, zeta=0.288)
assert abs(clearshape.residual_vibration(s, 3.32, 0.288)) < 1e-12
print('installed python module:', clearshape.__file__, s)
import importlib.metadata as md
cli = '$("$prefix/bin/clearshape" --version)'
assert md.version('clearshape') == clearshape.__version__ and cli == 'clearshape ' + clearshape.__version__, (md.version('clearshape'), clearshape.__version__, cli)
assert str(md.distribution('clearshape').locate_file('clearshape')).startswith('$prefix')
print('installed python metadata:', md.version('clearshape'))
"
echo "install_test: ok ($prefix)"
