#!/usr/bin/python3
"""Draws the figure of `clearshape recommend --plot`.

    /usr/bin/python3 python/plot_recommend.py <data.json> <out.png>

<data.json> is written by the command: the measured spectra (frequency_hz, power, label), the
modes (frequency_hz, frequency_std_hz), and every candidate's worst-case residual vibration
V(f) (max over the test damping ratios and frequency scales) on a frequency grid, with its
fitted design frequency, remaining vibration and delay. As Klipper's calibrate_shaper graph:
the spectrum on the left axis, the shapers' vibration-reduction curves on the right; the
recommended shaper is drawn thick. Style: python/clearshape_plot (the study's figures); PNG
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


def draw(data: dict):
    use_style()
    fig, ax = plt.subplots(figsize=(7.2, 5.4))
    for i, s in enumerate(data["spectra"]):
        ax.plot(s["frequency_hz"], s["power"], color=SPECTRUM_COLOURS[i % len(SPECTRUM_COLOURS)], linewidth=1.6,
                label=f"PSD {s['label']}", zorder=3)
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("power spectral density (unit²/Hz)")
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
    ax.legend(lines + more, labels + more_labels, loc="upper center", bbox_to_anchor=(0.5, -0.13), fontsize=6.5,
              ncol=2)
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
    fig.savefig(argv[1], dpi=150, metadata=PNG_METADATA)
    plt.close(fig)
    return 0


if __name__ == "__main__":
    sys.exit(main())
