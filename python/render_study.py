#!/usr/bin/python3
"""Draws a clearshape study's figures and writes its report.

    /usr/bin/python3 python/render_study.py <out>

<out> is a study output folder (clearshape study ... --out <out>): results.json, figures.json,
runs/. Writes <out>/figures/<id>.png (150 dpi) and .pdf for every entry of figures.json, then
<out>/report.html (self-contained). Prints the report's path on stdout; progress on stderr.
Exit codes: 0 every figure drawn; 1 the report was written but some figure could not be drawn
(each is named on stderr and in the report); 2 bad input (missing or invalid results.json).
"""
from __future__ import annotations

import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import make_report  # noqa: E402
from clearshape_plot.data import StudyDataError, read_json  # noqa: E402
from clearshape_plot.figures import draw_all  # noqa: E402


def log(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 1 or argv[0] in ("-h", "--help"):
        print("usage: render_study.py <study-output-folder>", file=sys.stderr)
        return 2
    out = Path(argv[0])
    try:
        results = read_json(out / "results.json")
        index = read_json(out / "figures.json") if (out / "figures.json").exists() else {"figures": []}
    except StudyDataError as e:
        log(f"render_study: {e}")
        return 2
    if not (out / "figures.json").exists():
        log(f"render_study: {out / 'figures.json'} not found; the report will have no figures")
    t0 = time.monotonic()
    specs = list(index.get("figures", []) or [])
    # The summary of the rig tables as a figure, from the tables, unless the study lists one.
    summary = make_report.md_summary_spec(results)
    if summary and not any(str(f.get("kind")) == "md-summary" for f in specs):
        specs.append(summary)
    n = len(specs)
    log(f"render_study: drawing {n} figures into {out / 'figures'}")
    records = draw_all(out, specs, log=log)
    failed = [r for r in records if r["error"]]
    log(f"render_study: {n - len(failed)} of {n} figures drawn in {time.monotonic() - t0:.1f} s")
    try:
        report = make_report.build(out, records)
    except StudyDataError as e:
        log(f"render_study: {e}")
        return 2
    log(f"render_study: report written: {report.resolve()}")
    print(report.resolve())
    return 1 if failed else 0


if __name__ == "__main__":
    raise SystemExit(main())
