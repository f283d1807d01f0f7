#!/usr/bin/python3
"""Draws the figure of `clearshape recommend --plot`.

    /usr/bin/python3 python/plot_recommend.py <data.json> <out.png>

<data.json> is written by the command (study::recommend_plot_data; fields in docs/recommend.md):
the measured spectra (frequency_hz, power, label, power_unit, a Klipper file's axes, the PSD the
recommended shaper leaves), the modes (frequency_hz, frequency_std_hz), every candidate's
worst-case residual vibration V(f) (max over the test damping ratios and frequency scales) on a
frequency grid with its fitted design frequency, remaining vibration and delay, and the design
offsets. As Klipper's calibrate_shaper graph: the spectrum (and X, Y, Z) on the left axis, the
PSD after the recommended shaper dashed, the shapers' vibration-reduction curves on the right;
the recommended shaper is drawn thick; why a design frequency sits away from its mode is written
under the axes. Style: python/clearshape_plot (the study's figures); PNG
metadata fixed, so the same data give the same bytes. Exit 0 drawn, 2 bad input.
"""
from __future__ import annotations

import json
import sys
import textwrap
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from clearshape_plot import roles  # noqa: E402
from clearshape_plot.figures import PNG_METADATA, use_style  # noqa: E402

SPECTRUM_COLOURS = ["#404040", "#7B3FA0", "#0072B2", "#D55E00"]
# Klipper's graph: X red, Y green, Z blue, the sum purple.
AXIS_STYLE = {"x": ("X", "#D62728"), "y": ("Y", "#2CA02C"), "z": ("Z", "#1F77B4"), "xyz": ("X+Y+Z", "#7B3FA0")}


def axis_key(column: str) -> str:
    return column.split("_")[-1]


def draw_spectrum(ax, i: int, s: dict):
    axes = s.get("axes") or []
    colour = SPECTRUM_COLOURS[i % len(SPECTRUM_COLOURS)]
    name = Path(str(s["label"]).split(" (")[0]).name
    for a in axes:
        label, c = AXIS_STYLE.get(axis_key(str(a["column"])), (str(a["column"]), colour))
        analysed = a["column"] == s.get("column")
        if analysed:
            colour = c
        ax.plot(s["frequency_hz"], a["power"], color=c, linewidth=1.6 if analysed else 0.9, alpha=1.0 if analysed else 0.8,
                label=f"{label} {name}" + (" (analysed)" if analysed else ""), zorder=3 if analysed else 2)
    if not axes:
        ax.plot(s["frequency_hz"], s["power"], color=colour, linewidth=1.6, label=f"PSD {s['label']}", zorder=3)
    if s.get("power_after_shaper") is not None:
        ax.plot(s["frequency_hz"], s["power_after_shaper"], color=colour, linewidth=1.4, linestyle=(0, (5, 2.5)),
                label=f"after the recommended shaper ({name}, P·V²)", zorder=5)


def power_unit(data: dict) -> str:
    units = sorted({str(s.get("power_unit") or "unit²/Hz") for s in data["spectra"]})
    return units[0] if len(units) == 1 else " | ".join(units)


def draw(data: dict):
    use_style()
    fig, ax = plt.subplots(figsize=(7.2, 5.4))
    for i, s in enumerate(data["spectra"]):
        draw_spectrum(ax, i, s)
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel(f"power spectral density ({power_unit(data)})")
    ax.set_ylim(bottom=0.0)
    for k, m in enumerate(data["modes"]):
        f, sd = float(m["frequency_hz"]), float(m["frequency_std_hz"])
        ax.axvspan(f - sd, f + sd, color="#d9d9d9", alpha=0.6, zorder=1, linewidth=0,
                   label="mode ± 1σ" if k == 0 else None)
        ax.axvline(f, color="#7A7A7A", linestyle=(0, (2, 2)), linewidth=0.9, zorder=2)
    right = ax.twinx()
    right.grid(False)
    right.spines["right"].set_visible(True)
    for i, c in enumerate(data["candidates"]):
        name = str(c["name"])
        style = roles.style_for(name, i) if "*" not in name else roles.style_for("", i)
        style = dict(style, linestyle=(0, (4, 1.5)) if "*" in name else "-")
        freqs = "+".join(f"{float(f):.2f}" for f in c["design_frequency_hz"])
        label = (f"{name.upper()} ({freqs} Hz, vibr. {100 * float(c['remaining_worst']):.1f} %, "
                 f"{1000 * float(c['duration_s']):.0f} ms)")
        if c.get("smoothing_mm") is not None:  # printer data: Klipper's smoothing and max acceleration
            accel = c.get("max_accel_mm_s2")
            label = (f"{name.upper()} ({freqs} Hz, {100 * float(c['remaining_worst']):.1f} %, "
                     f"{1000 * float(c['duration_s']):.0f} ms, {float(c['smoothing_mm']):.3f} mm"
                     + (f", ≤ {100 * round(float(accel) / 100):.0f} mm/s²)" if accel is not None else ")"))
        if c.get("chosen"):
            style.update(linewidth=2.6, zorder=6)
            label += " — recommended"
        else:
            style.update(linewidth=1.0, alpha=0.85, zorder=4)
        right.plot(data["frequency_hz"], c["response"], label=label, **style)
    right.set_ylim(0.0, 1.05)
    right.set_ylabel("residual vibration V (worst case)")
    lines, labels = ax.get_legend_handles_labels()
    more, more_labels = right.get_legend_handles_labels()
    ax.legend(lines + more, labels + more_labels, loc="upper center", bbox_to_anchor=(0.5, -0.21), fontsize=6.5,
              ncol=2)
    offsets = [str(d["reason"]) for d in data.get("design_offsets") or []]
    if offsets:  # one line each: why a design frequency sits more than 1σ from its mode
        ax.text(-0.08, -0.145, "\n".join(textwrap.shorten(o, 185, placeholder=" …") for o in offsets),
                transform=ax.transAxes, fontsize=5.4, color="#444444", va="top")
    reason = str(data.get("reason") or "")
    ax.set_title("Recommended input shaper", loc="left")
    if reason:
        fig.suptitle("\n".join(textwrap.wrap(reason, 120)[:3]), x=0.01, ha="left", fontsize=7, fontweight="normal",
                     color="#444444")
    return fig


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 2:
        print("usage: plot_recommend.py <data.json> <out.png>", file=sys.stderr)
        return 2
    try:
        data = json.loads(Path(argv[0]).read_text(encoding="utf-8"))
        fig = draw(data)
    except (OSError, ValueError, KeyError, TypeError) as e:
        print(f"plot_recommend: {argv[0]}: {e}", file=sys.stderr)
        return 2
    fig.savefig(argv[1], dpi=150, metadata=PNG_METADATA, bbox_inches="tight")  # the legend and notes whole
    plt.close(fig)
    return 0


if __name__ == "__main__":
    sys.exit(main())
