#!/usr/bin/env bash
# Installs the Debian packages clearshape needs to build, test, benchmark and report.
# Idempotent: does nothing when every package is already installed.
# Usage: scripts/install-deps.sh           what make run / make test need
#        scripts/install-deps.sh --fuzz    what make fuzz needs (clang, its sanitizer runtimes)
# Chromium (headless) is always installed: the report test opens report.html in it.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libeigen3-dev libsundials-dev libceres-dev libnlopt-cxx-dev
  libcli11-dev libtomlplusplus-dev nlohmann-json3-dev libfmt-dev libspdlog-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  python3 python3-numpy python3-scipy python3-matplotlib python3-jinja2
  pybind11-dev python3-dev python3-pytest python3-h5py python3-distributed
  chromium fonts-dejavu-core
  gcc-avr avr-libc simavr libsimavr-dev libserialport-dev
  rt-tests
)

if [[ "${1:-}" == "--fuzz" ]]; then
  packages=(clang libclang-rt-14-dev)
fi

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
