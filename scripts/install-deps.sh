#!/usr/bin/env bash
# Installs the Debian packages clearshape needs to build, test, benchmark and report.
# Idempotent: does nothing when every package is already installed.
# Usage: scripts/install-deps.sh           everything: what make test / make bench need
#        scripts/install-deps.sh --run     what make run needs: the CLI's build and the figures
#        scripts/install-deps.sh --fuzz    what make fuzz needs (clang, its sanitizer runtimes)
# Chromium (headless) comes with the full set: the report test opens report.html in it.
set -euo pipefail

# make run: build the library and the CLI (the Python module is configured, so pybind11 and
# the Python headers are needed to configure, not to build), then draw the figures and the
# report (python/render_study.py: matplotlib, jinja2). The CLI links every module, the arm's
# URDF reader (urdfdom) and rigid-body dynamics (Orocos KDL) included (docs/arm.md).
run_packages=(
  build-essential cmake pkg-config ninja-build
  libeigen3-dev libsundials-dev libceres-dev libnlopt-cxx-dev libboost-dev
  libcli11-dev libtomlplusplus-dev nlohmann-json3-dev libfmt-dev libserialport-dev
  pybind11-dev python3-dev
  liburdfdom-dev liborocos-kdl-dev
  python3 python3-numpy python3-matplotlib python3-jinja2 fonts-dejavu-core
)
# make test adds the test frameworks, SciPy (golden data), the firmware tool chain and simavr,
# Chromium (with ChromeDriver and Selenium: the report on an emulated phone), what sweeps and the
# real-time checks use, help2man (the .deb's man page), lintian (the .debs' check,
# tests/package/deb_test.sh), build, wheel and venv (the Python wheel in a venv,
# tests/package/wheel_test.sh) and MuJoCo (the independent reference of the arm's rigid-body
# dynamics, tests/arm/test_mujoco.cpp).
packages=(
  "${run_packages[@]}"
  libspdlog-dev libgtest-dev libgmock-dev libbenchmark-dev
  python3-scipy python3-pytest python3-h5py python3-distributed
  help2man lintian python3-build python3-wheel python3-venv libmujoco-dev
  chromium chromium-driver python3-selenium
  gcc-avr avr-libc simavr libsimavr-dev
  rt-tests
)

case "${1:-}" in
  --run) packages=("${run_packages[@]}") ;;
  --fuzz) packages=(clang libclang-rt-14-dev) ;;
  "") ;;
  *) echo "usage: scripts/install-deps.sh [--run|--fuzz]" >&2; exit 2 ;;
esac

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [[ ${#missing[@]} -eq 0 ]]; then
  exit 0
fi

echo "clearshape: installing missing Debian packages: ${missing[*]}" >&2
SUDO=""
if [[ "$(id -u)" -ne 0 ]]; then
  if command -v sudo >/dev/null; then SUDO="sudo"; else
    echo "clearshape: not root and no sudo; install these packages first: ${missing[*]}" >&2
    exit 2
  fi
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
