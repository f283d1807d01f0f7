#!/usr/bin/env bash
# The main job of `make run`: the thesis's experimental programme (Chapters 4–5, Appendix B) on
# the simulated thesis rig in both operation modes (clearshape study), then the figures and the
# self-contained report of each study (python/render_study.py, Debian's python3-matplotlib).
# Finished runs are reused by a second `make run` (out/thesis-*/runs/); tables on stdout go to
# out/thesis-*/tables.md as well.
set -euo pipefail
build_dir="${1:-build}"
exe="$build_dir/bin/clearshape"
mkdir -p out
for mode in position speed; do
  "$exe" study "studies/thesis-$mode.toml" --out "out/thesis-$mode" > /dev/null
done
reports=()
if [[ -f python/render_study.py ]]; then
  for mode in position speed; do
    if ! /usr/bin/python3 python/render_study.py "out/thesis-$mode" > /dev/null; then
      echo "clearshape: warning: some figures of out/thesis-$mode failed to draw; report.html names them" >&2
    fi
    [[ -f "out/thesis-$mode/report.html" ]] && reports+=("$(pwd)/out/thesis-$mode/report.html")
  done
fi
echo
for mode in position speed; do
  echo "Thesis $mode mode: tables out/thesis-$mode/tables.md, data out/thesis-$mode/results.json"
done
if (( ${#reports[@]} > 0 )); then
  for r in "${reports[@]}"; do echo "Report: $r"; done
else
  echo "Report: out/thesis-position/tables.md and out/thesis-speed/tables.md"
fi
