#!/usr/bin/python3
"""Draws a MATLAB-style `compare` + `resid` figure for `clearshape identify`.

    clearshape identify --data run.csv --simulated sim.csv --json > identify.json
    /usr/bin/python3 python/plot_compare.py identify.json sim.csv compare.png

Top: the measured output and the model's simulation (NRMSE fit %, as MATLAB `compare`); middle:
the residual e = measured − simulated; bottom: the residual tests of `identify` (docs/frf.md) —
the residual's autocorrelation for lags 0 … M and the input–residual cross-correlation for lags
−M … M, each with its confidence band (shaded) and its verdict with the p-value. Style:
python/clearshape_plot; PNG metadata fixed, so the same data give the same bytes; the PNG is
written to a temporary name and renamed. Exit 0 drawn, 2 bad input.
"""
from __future__ import annotations

import csv
import json
import os
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from clearshape_plot.figures import PNG_METADATA, use_style  # noqa: E402

MEASURED, SIMULATED, RESIDUAL, BAND = "#404040", "#0072B2", "#D55E00", "#d9d9d9"


def read_simulated(path: str) -> dict:
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    if not rows or not {"time_s", "measured", "simulated"} <= set(rows[0]):
        raise ValueError("expected the columns time_s, measured, simulated (identify --simulated)")
    return {k: [float(r[k]) for r in rows] for k in ("time_s", "measured", "simulated")}


def correlation_panel(ax, test: dict | None, title: str, verdict_key: str):
    if test is None:
        ax.text(0.5, 0.5, "not tested", ha="center", va="center", transform=ax.transAxes)
        ax.set_title(title)
        return
    lags, r, band = test["lags"], test["correlation"], float(test["band"])
    ax.axhspan(-band, band, color=BAND, linewidth=0, zorder=1)
    ax.vlines(lags, 0.0, r, color=RESIDUAL, linewidth=1.4, zorder=3)
    ax.plot(lags, r, "o", color=RESIDUAL, markersize=2.5, zorder=4)
    ax.axhline(0.0, color="#7A7A7A", linewidth=0.8, zorder=2)
    verdict = verdict_key if test[verdict_key] else "NOT " + verdict_key
    ax.set_title(f"{title}\n{verdict}, p = {float(test['p_value']):.2g}, band ±{band:.2g}", fontsize="medium")
    ax.set_xlabel("lag (samples)")


def draw(result: dict, sim: dict):
    use_style()
    fig = plt.figure(figsize=(7.6, 8.0), constrained_layout=True)
    grid = fig.add_gridspec(3, 2, height_ratios=[1.3, 0.8, 1.0])
    top = fig.add_subplot(grid[0, :])
    top.plot(sim["time_s"], sim["measured"], color=MEASURED, linewidth=1.2, label="measured")
    top.plot(sim["time_s"], sim["simulated"], color=SIMULATED, linewidth=1.2, linestyle=(0, (4, 1.5)),
             label=f"{result['model']} simulated, fit {float(result['fit_percent']):.2f} %")
    top.set_ylabel("output")
    top.set_title(f"compare: {result['model']} on {result['experiments'][0]['name']}")
    top.legend(loc="best", fontsize="small")
    mid = fig.add_subplot(grid[1, :], sharex=top)
    residual = [m - s for m, s in zip(sim["measured"], sim["simulated"])]
    mid.plot(sim["time_s"], residual, color=RESIDUAL, linewidth=0.9)
    mid.axhline(0.0, color="#7A7A7A", linewidth=0.8)
    mid.set_ylabel("residual")
    mid.set_xlabel("time (s)")
    tests = result["residual_tests"]["experiments"][0]
    correlation_panel(fig.add_subplot(grid[2, 0]), tests["whiteness"], "residual autocorrelation", "white")
    correlation_panel(fig.add_subplot(grid[2, 1]), tests["independence"], "input–residual correlation", "independent")
    return fig


def save_atomic(fig, png: str) -> None:
    tmp = f"{png}.tmp{os.getpid()}"
    try:
        fig.savefig(tmp, dpi=150, format="png", metadata=PNG_METADATA)
        os.replace(tmp, png)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 3:
        print("usage: plot_compare.py <identify.json> <simulated.csv> <out.png>", file=sys.stderr)
        return 2
    try:
        result = json.loads(Path(argv[0]).read_text(encoding="utf-8"))
        if "residual_tests" not in result:
            raise ValueError("no residual_tests: give the --json of `clearshape identify` (not --crossval)")
        fig = draw(result, read_simulated(argv[1]))
    except (OSError, ValueError, KeyError, TypeError, IndexError) as e:
        print(f"plot_compare: {e}", file=sys.stderr)
        return 2
    save_atomic(fig, argv[2])
    plt.close(fig)
    return 0


if __name__ == "__main__":
    sys.exit(main())
