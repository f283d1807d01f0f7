#!/usr/bin/env bash
# The main job of `make run`: the thesis's experimental programme (Chapters 4–5, Appendix B) on
# the simulated thesis rig in both operation modes, on the worn-coupling rig (docs/worn-coupling.md)
# and on the large-play rig (clearshape study;
# docs/large-play.md), then the figures and the self-contained report of each study
# (python/render_study.py, Debian's python3-matplotlib); then the arm studies of issue 24
# (clearshape arm study; docs/arm.md) and their reports (python/render_arm_study.py).
# Finished runs are reused by a second `make run` (out/thesis-*/runs/); tables on stdout go to
# out/thesis-*/tables.md as well.
set -euo pipefail
build_dir="${1:-build}"
exe="$build_dir/bin/clearshape"
mkdir -p out
studies=(thesis-position thesis-speed worn-coupling-position large-play-position)
arm_studies=(arm-scara2 arm-vertical2)
# A study's report (one single-threaded Python process) is drawn while the next study runs.
render=()
[[ -f python/render_study.py ]] && render=(/usr/bin/python3 python/render_study.py)
pids=()
drawn=()  # the study of each pid
trap 'for p in "${pids[@]}"; do kill "$p" 2> /dev/null || true; done' EXIT  # a study failed
for s in "${studies[@]}"; do
  "$exe" study "studies/$s.toml" --out "out/$s" > /dev/null
  # README's figure is this study's rig-B.1, redrawn on every run (python/readme_figure.py).
  if [[ $s == thesis-position && ${#render[@]} -gt 0 ]]; then
    /usr/bin/python3 python/readme_figure.py "out/$s" docs/figures/step20-zvdd.png
  fi
  if (( ${#render[@]} > 0 )); then
    "${render[@]}" "out/$s" > /dev/null &
    pids+=($!)
    drawn+=("$s")
  fi
done
for s in "${arm_studies[@]}"; do
  "$exe" arm study "studies/$s.toml" --out "out/$s" > /dev/null
  if (( ${#render[@]} > 0 )); then
    /usr/bin/python3 python/render_arm_study.py "out/$s" > /dev/null &
    pids+=($!)
    drawn+=("$s")
  fi
done
reports=()
for i in "${!pids[@]}"; do
  s=${drawn[$i]}
  if ! wait "${pids[$i]}"; then
    echo "clearshape: warning: some figures of out/$s failed to draw; report.html names them" >&2
  fi
  [[ -f "out/$s/report.html" ]] && reports+=("$(pwd)/out/$s/report.html")
done
pids=()
echo
for s in "${studies[@]}" "${arm_studies[@]}"; do
  echo "$s: tables out/$s/tables.md, data out/$s/results.json"
done
if (( ${#reports[@]} > 0 )); then
  for r in "${reports[@]}"; do echo "Report: $r"; done
else
  echo "Report: out/<study>/tables.md for ${studies[*]} ${arm_studies[*]}"
fi
# The numbers README.md and docs/*.md quote from these studies (their doc-numbers markers) are what
# the studies just wrote (issue 22, item 13): a drifted quote fails the run, naming the doc's line.
if ! /usr/bin/python3 scripts/check-doc-numbers.py --out out; then
  echo "clearshape: the docs quote numbers these studies no longer give (listed above): update the docs" >&2
  exit 1
fi
