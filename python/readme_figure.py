#!/usr/bin/env python3
"""Draws one figure of a study output folder to a given PNG, exactly as the report draws it.

usage: readme_figure.py <study-output-folder> <out.png> [--figure ID]

`make run` (scripts/run-main.sh) draws README's figure with it from out/thesis-position:
the report's rig-B.1 (thesis Fig. 5.19 analogue), so README never shows a figure the current
study does not produce. Beside the PNG it writes <out>.json: the figure's id, title and legend
texts (which carry Eq. 5.1's numbers); tests/report draws a fresh one and compares that record,
so a stale README figure fails a test. Both files are written through a temporary file in the
same folder and a rename, the PNG with the report's fixed metadata.
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import matplotlib.pyplot as plt  # noqa: E402

from clearshape_plot.data import CsvCache, StudyDataError, read_json  # noqa: E402
from clearshape_plot.figures import PNG_METADATA, draw, figure_id, use_style  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("study", type=Path, help="a study output folder (clearshape study ... --out DIR)")
    ap.add_argument("png", type=Path, help="the PNG to write")
    ap.add_argument("--figure", default="rig-B.1", help="the figure's id in DIR/figures.json (default rig-B.1)")
    a = ap.parse_args(argv)
    index_path = a.study / "figures.json"
    if not index_path.exists():
        print(f"readme_figure: {index_path} not found: give a study output folder", file=sys.stderr)
        return 2
    specs = read_json(index_path).get("figures", [])
    found = [(i, s) for i, s in enumerate(specs) if figure_id(s, i) == a.figure]
    if not found:
        known = ", ".join(figure_id(s, i) for i, s in enumerate(specs))
        print(f"readme_figure: --figure {a.figure}: not in {index_path} (it has: {known})", file=sys.stderr)
        return 2
    use_style()
    index, spec = found[0]
    try:
        fig = draw(spec, CsvCache(a.study), index)
    except StudyDataError as e:
        print(f"readme_figure: {a.study}: {e}", file=sys.stderr)
        return 1
    record = {"figure": a.figure, "title": fig._suptitle.get_text() if fig._suptitle else "",
              "legend": [t.get_text() for ax in fig.axes if ax.get_legend() for t in ax.get_legend().get_texts()]}
    a.png.parent.mkdir(parents=True, exist_ok=True)
    write_atomic(a.png, lambda path: fig.savefig(path, dpi=150, format="png", metadata=PNG_METADATA))
    plt.close(fig)
    sidecar = a.png.with_suffix(".json")
    write_atomic(sidecar, lambda path: Path(path).write_text(json.dumps(record, indent=2, ensure_ascii=False) + "\n",
                                                           encoding="utf-8"))
    return 0


def write_atomic(target: Path, write) -> None:
    """write(path) into a temporary file beside target, then rename it over target."""
    fd, tmp = tempfile.mkstemp(dir=target.parent, prefix=".incomplete.", suffix=target.suffix)
    os.close(fd)
    try:
        write(tmp)
        os.chmod(tmp, 0o644)
        os.replace(tmp, target)
    except BaseException:
        os.unlink(tmp)
        raise


if __name__ == "__main__":
    sys.exit(main())
