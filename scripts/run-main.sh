#!/usr/bin/env bash
# The main job of `make run`. Until the thesis study lands it demonstrates shaping a step on
# the thesis's speed-mode drive model and writes the result under out/demo/.
set -euo pipefail
build_dir="${1:-build}"
exe="$build_dir/bin/clearshape"
"$exe" demo --out out/demo
