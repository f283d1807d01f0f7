#!/usr/bin/env bash
# The Python package as Python users install it (docs/python.md, "A wheel for a venv"), offline:
#   1. `python3 -m build --no-isolation` on <build>/python-dist makes an sdist and, from it, a
#      wheel tagged for this Python and platform, whose metadata names the CLI's version, numpy,
#      the extras and the Python range, and which holds the extension, the stub and py.typed;
#   2. `pip install --no-index` of the wheel into a `python3 -m venv --system-site-packages` venv
#      (numpy from the system) works; the venv imports clearshape from its own site-packages,
#      designs a shaper, importlib.metadata.version("clearshape") answers the CLI's version, and
#      `pip uninstall` removes every file it installed.
# Usage: wheel_test.sh BUILD_DIR PYTHON
set -euo pipefail
build=$1 python=$2
work=$(mktemp -d "${TMPDIR:-/tmp}/clearshape-wheel-test.XXXXXX")
trap 'rm -rf "$work"' EXIT
fail() { echo "wheel_test: $*" >&2; exit 1; }
unset PYTHONPATH  # nothing from the build tree: the venv must find clearshape in the wheel only
version=$("$build/bin/clearshape" --version | sed 's/^clearshape //')
"$python" -c "import build, wheel, venv" 2> /dev/null \
  || fail "$python lacks build, wheel or venv (Debian: python3-build python3-wheel python3-venv; scripts/install-deps.sh)"

# 1. sdist and wheel.
"$python" -m build --no-isolation --outdir "$work/dist" "$build/python-dist" > "$work/build.log" 2>&1 \
  || { cat "$work/build.log" >&2; fail "python3 -m build failed"; }
tag=$("$python" -c 'import sys; print(f"cp{sys.version_info[0]}{sys.version_info[1]}")')
wheel=$work/dist/clearshape-$version-$tag-$tag-linux_$(uname -m).whl
sdist=$work/dist/clearshape-$version.tar.gz
[[ -f $wheel && -f $sdist ]] || fail "want $(basename "$wheel") and $(basename "$sdist"), got: $(ls "$work/dist")"
"$python" - "$wheel" "$sdist" "$version" <<'EOF' || fail "the wheel's or sdist's contents or metadata are wrong"
import sys, tarfile, zipfile
from email.parser import Parser
wheel, sdist, version = sys.argv[1:]
z = zipfile.ZipFile(wheel)
names = z.namelist()
for want in ("clearshape/__init__.py", "clearshape/__init__.pyi", "clearshape/py.typed", "clearshape/sweep.py"):
    assert want in names, (want, names)
assert any(n.startswith("clearshape/_core") and n.endswith(".so") for n in names), names
assert not any("__pycache__" in n for n in names), names
meta = Parser().parsestr(z.read(f"clearshape-{version}.dist-info/METADATA").decode())
assert meta["Name"] == "clearshape" and meta["Version"] == version, (meta["Name"], meta["Version"])
requires = meta.get_all("Requires-Dist")
assert "numpy" in requires and any(r.startswith("h5py") and "sweep" in r for r in requires), requires
assert set(meta.get_all("Provides-Extra")) == {"sweep", "cluster"}, meta.get_all("Provides-Extra")
major, minor = sys.version_info[:2]
assert set(meta["Requires-Python"].split(",")) == {f">={major}.{minor}", f"<{major}.{minor + 1}"}, meta["Requires-Python"]
wheel_info = z.read(f"clearshape-{version}.dist-info/WHEEL").decode()
assert "Root-Is-Purelib: false" in wheel_info, wheel_info
members = tarfile.open(sdist).getnames()
for want in ("PKG-INFO", "pyproject.toml", "setup.py", "LICENSE", "clearshape/__init__.py"):
    assert f"clearshape-{version}/{want}" in members, (want, members)
print("wheel_test:", len(names), "files in the wheel,", len(members), "in the sdist")
EOF

# 2. A venv with the system's numpy; pip offline.
"$python" -m venv --system-site-packages "$work/venv"
venv_python=$work/venv/bin/python
"$venv_python" -m pip install --no-index --no-cache-dir --disable-pip-version-check "$wheel" > "$work/pip.log" 2>&1 \
  || { cat "$work/pip.log" >&2; fail "pip install --no-index of the wheel failed"; }
(cd "$work" && "$venv_python" - "$work/venv" "$version" <<'EOF') || fail "the venv does not import the installed wheel"
import importlib.metadata as md, sys
import clearshape
venv, version = sys.argv[1:]
assert clearshape.__file__.startswith(venv + "/lib/"), clearshape.__file__
assert md.version("clearshape") == clearshape.__version__ == version, (md.version("clearshape"), clearshape.__version__, version)
assert str(md.distribution("clearshape").locate_file("clearshape")).startswith(venv)
s = clearshape.design("zvd", frequency_hz=3.32, zeta=0.288)
assert abs(clearshape.residual_vibration(s, 3.32, 0.288)) < 1e-12
print("wheel_test: venv imports", clearshape.__file__, "version", md.version("clearshape"), s)
EOF
"$venv_python" -m pip uninstall -y --disable-pip-version-check clearshape > "$work/uninstall.log" 2>&1 \
  || { cat "$work/uninstall.log" >&2; fail "pip uninstall failed"; }
left=$(find "$work/venv/lib" -path "*site-packages/clearshape*" -not -name "*.pyc")
[[ -z $left ]] || fail "pip uninstall left: $left"
echo "wheel_test: ok — $(basename "$wheel"), $(basename "$sdist")"
