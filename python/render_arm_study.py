#!/usr/bin/python3
"""Draws the arm study's figures and writes its report (docs/arm.md, "The arm study").

    /usr/bin/python3 python/render_arm_study.py <out>

<out> is the folder `clearshape arm study FILE --out <out>` wrote (results.json, tables.md).
Writes <out>/figures/residual.png (tool-tip residual per design, mm and % removed),
mode-map.png (the lowest linearised mode f(q1, q2) over the joint grid and over the workspace,
the arm drawn at the workspace centre) and improvement.png (each move's end pose coloured by
the improvement of each design on that move), then <out>/report.html, self-contained (figures
embedded as base64). The same results.json gives the same bytes. Prints the report's path.
Exit codes: 0 done; 2 bad input (missing or invalid results.json).
"""
from __future__ import annotations

import base64
import html
import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from clearshape_plot.figures import PNG_METADATA, use_style  # noqa: E402

AXES = "xyz"


def read_results(out: Path) -> dict:
    path = out / "results.json"
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as e:
        raise SystemExit(f"render_arm_study: {path}: {e}") from None
    for key in ("study", "designs", "moves", "mode_map", "drawing"):
        if key not in doc:
            raise SystemExit(f"render_arm_study: {path}: key '{key}' is missing; not an arm study's results.json")
    return doc


def plane(doc: dict) -> tuple[int, int]:
    """The two tool coordinates that move most over the map's poses (x–y for a SCARA, x–z for a vertical arm)."""
    tool = np.array([p["tool_m"] for p in doc["mode_map"]["poses"]])
    spread = np.ptp(tool, axis=0)
    a, b = sorted(np.argsort(spread)[-2:])
    return int(a), int(b)


def draw_arm(ax, doc: dict, axes: tuple[int, int], colour: str = "0.2") -> None:
    pts = np.array(doc["drawing"]["points_m"])
    ax.plot(pts[:, axes[0]], pts[:, axes[1]], "-o", color=colour, lw=3, ms=5, zorder=5,
            label="arm at the workspace centre")


def workspace_frame(ax, doc: dict, axes: tuple[int, int]) -> None:
    """Equal axes around every map pose's tool, the arm and the moves' ends, with a margin."""
    pts = np.vstack([np.array([p["tool_m"] for p in doc["mode_map"]["poses"]]), np.array(doc["drawing"]["points_m"]),
                     np.array([m["tool_end_m"] for m in doc["moves"]])])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    pad = 0.08 * max(hi[axes[0]] - lo[axes[0]], hi[axes[1]] - lo[axes[1]])
    ax.set_xlim(lo[axes[0]] - pad, hi[axes[0]] + pad)
    ax.set_ylim(lo[axes[1]] - pad, hi[axes[1]] + pad)
    ax.set_aspect("equal")
    ax.set_xlabel(f"tool {AXES[axes[0]]} (m)")
    ax.set_ylabel(f"tool {AXES[axes[1]]} (m)")


def lowest_hz(doc: dict) -> np.ndarray:
    return np.array([min(p["natural_frequency_hz"]) for p in doc["mode_map"]["poses"]])


def save(fig, path: Path) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120, metadata=PNG_METADATA)
    plt.close(fig)


def residual_figure(doc: dict, path: Path) -> None:
    designs = doc["designs"]
    names = [d["name"] for d in designs]
    mm = [d["total_residual_mm"] for d in designs]
    colours = ["0.5"] + ["tab:red" if d["worse_than_unshaped"] else "tab:blue" for d in designs[1:]]
    fig, ax = plt.subplots(figsize=(7, 3.6))
    ax.set_axisbelow(True)
    bars = ax.bar(names, mm, color=colours)
    for bar, d in zip(bars, designs):
        text = "reference" if d is designs[0] else f"{100 * d['improvement']:.1f} % removed"
        if d["worse_than_unshaped"]:
            text = f"{100 * d['improvement']:.1f} %: WORSE"
        ax.annotate(f"{d['total_residual_mm']:.3f} mm\n{text}", (bar.get_x() + bar.get_width() / 2, bar.get_height()),
                    ha="center", va="bottom", fontsize=8)
    ax.set_ylabel("Σ tool residual over the moves (mm)")
    ax.set_ylim(0, 1.3 * max(mm + [1e-9]))
    ax.set_title(f"{doc['study']['arm']}: {len(doc['moves'])} moves, Eq. 5.1 on the tool position")
    fig.tight_layout()
    save(fig, path)


def mode_map_figure(doc: dict, path: Path) -> None:
    joints = doc["mode_map"]["joints"]
    f = lowest_hz(doc)
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.4))
    norm = matplotlib.colors.Normalize(vmin=f.min(), vmax=f.max())
    if len(joints) == 2:
        q1, q2 = (np.degrees(j["angles_rad"]) for j in joints)
        left.grid(False)
        mesh = left.pcolormesh(q2, q1, f.reshape(len(q1), len(q2)), shading="nearest", cmap="viridis", norm=norm)
        ends = np.degrees([m["to_rad"][:2] for m in doc["moves"]])
        left.plot(ends[:, 1], ends[:, 0], "w.", ms=5, label="move end poses")
        left.set_xlabel(f"{joints[1]['name']} q2 (deg)")
        left.set_ylabel(f"{joints[0]['name']} q1 (deg)")
        left.legend(loc="upper right", fontsize=7)
    else:
        q1 = np.degrees(joints[0]["angles_rad"])
        left.plot(q1, f)
        left.set_xlabel(f"{joints[0]['name']} q1 (deg)")
        left.set_ylabel("lowest mode (Hz)")
        mesh = None
    left.set_title("lowest linearised mode f(q1, q2) (Hz)")
    axes = plane(doc)
    tool = np.array([p["tool_m"] for p in doc["mode_map"]["poses"]])
    sc = right.scatter(tool[:, axes[0]], tool[:, axes[1]], c=f, cmap="viridis", norm=norm, s=14)
    draw_arm(right, doc, axes)
    workspace_frame(right, doc, axes)
    right.set_title("the same over the workspace (tool position)")
    right.legend(loc="lower left", fontsize=7)
    fig.colorbar(mesh if mesh is not None else sc, ax=[left, right], label="lowest mode (Hz)")
    save(fig, path)


def improvement_figure(doc: dict, path: Path) -> None:
    shaped = [d["name"] for d in doc["designs"][1:]]
    axes = plane(doc)
    fig, panels = plt.subplots(1, max(1, len(shaped)), figsize=(4 * max(1, len(shaped)) + 1.5, 4.6), squeeze=False)
    ends = np.array([m["tool_end_m"] for m in doc["moves"]])
    sc = None
    for ax, name in zip(panels[0], shaped):
        imp = np.array([np.nan if m["designs"][name]["improvement"] is None else m["designs"][name]["improvement"]
                        for m in doc["moves"]])
        worse = imp < 0
        draw_arm(ax, doc, axes, colour="0.75")
        sc = ax.scatter(ends[:, axes[0]], ends[:, axes[1]], c=np.clip(imp, -1, 1), cmap="RdBu", vmin=-1, vmax=1,
                        s=40, edgecolors="k", linewidths=0.4, zorder=6)
        ax.scatter(ends[worse, axes[0]], ends[worse, axes[1]], marker="x", c="k", s=60, zorder=7,
                   label="worse than unshaped")
        ax.set_title(f"{name}: {int(worse.sum())} of {len(imp)} moves worse", fontsize=9)
        workspace_frame(ax, doc, axes)
    handles, labels = panels[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="upper center", ncol=2, fontsize=8, frameon=False)
    if sc is not None:
        fig.colorbar(sc, ax=list(panels[0]), label="1 − shaped/unshaped on the move")
    save(fig, path)


def embedded(path: Path, alt: str) -> str:
    data = base64.b64encode(path.read_bytes()).decode("ascii")
    return f'<figure><img alt="{html.escape(alt)}" src="data:image/png;base64,{data}"><figcaption>{html.escape(alt)}</figcaption></figure>'


def warnings(doc: dict) -> list[str]:
    """Every place a design is worse than unshaped, said plainly."""
    out = []
    ref = doc["designs"][0]["name"]
    for d in doc["designs"][1:]:
        name = d["name"]
        if d["worse_than_unshaped"]:
            out.append(f"{name} is WORSE than unshaped over the whole benchmark: {d['total_residual_mm']:.4f} mm against "
                       f"{doc['designs'][0]['total_residual_mm']:.4f} mm.")
        worse = [(m["index"], m["designs"][name]["residual_mm"], m["designs"][ref]["residual_mm"]) for m in doc["moves"]
                 if m["designs"][name]["residual_mm"] > m["designs"][ref]["residual_mm"]]
        if worse:
            listed = "; ".join(f"move {i}: {s:.3g} mm against {u:.3g} mm" for i, s, u in worse)
            out.append(f"{name} is worse than unshaped on {len(worse)} of {len(doc['moves'])} moves ({listed}).")
    designed = [(m["index"], m["clearance_aware_design"]["worst_ratio"]) for m in doc["moves"]
                if m.get("clearance_aware_design", {}).get("worse_than_unshaped")]
    if designed:
        listed = "; ".join(f"move {i}: {r:.2f} times unshaped" for i, r in designed)
        out.append(f"clearance-aware: its design leaves more than unshaped from at least one of its start places in the "
                   f"plays on {len(designed)} of {len(doc['moves'])} moves — {listed}; the benchmark above plays every move from the middle of "
                   f"the plays.")
    return out


def table(rows: list[list[str]], header: list[str]) -> str:
    head = "".join(f"<th>{html.escape(h)}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{html.escape(c)}</td>" for c in r) + "</tr>" for r in rows)
    return f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


def flank_text(doc: dict) -> str:
    """The flank-keeping stop's margin and floor, when the study runs a flank design."""
    f = doc["study"].get("flank_keeping")
    if f is None or not any(d["name"].startswith("flank-") for d in doc["designs"]):
        return ""
    return (f"; flank designs: each move re-planned with the acceleration limits lowered to {f['margin']:g} × "
            f"|g_i| / M_ii at its end pose, never below {f['floor']:g} of the limit")


def report(doc: dict, figures: list[tuple[Path, str]]) -> str:
    s = doc["study"]
    joints = ", ".join(f"{j['name']} {j['play_deg']:.2f}° play, limits {j['velocity_rad_s']:g} rad/s, "
                       f"{j['acceleration_rad_s2']:g} rad/s², {j['jerk_rad_s3']:g} rad/s³" for j in s["joints"])
    design_rows = [[d["name"], f"{d['total_residual_mm']:.4f}",
                    "—" if i == 0 else f"{100 * d['improvement']:.1f} %" + (" (WORSE)" if d["worse_than_unshaped"] else ""),
                    "—" if i == 0 else str(d["moves_worse_than_unshaped"]),
                    f"{d['mean_command_s']:.3f} / {d['max_command_s']:.3f}" if "mean_command_s" in d else "—"]
                   for i, d in enumerate(doc["designs"])]
    names = [d["name"] for d in doc["designs"]]
    move_rows = [[str(m["index"]), ", ".join(f"{q:.3f}" for q in m["to_rad"])] +
                 [f"{m['designs'][n]['residual_mm']:.4f}" for n in names] for m in doc["moves"]]
    f = lowest_hz(doc)
    warn = warnings(doc)
    warn_html = ("<ul class=warn>" + "".join(f"<li>{html.escape(w)}</li>" for w in warn) + "</ul>") if warn else \
        "<p>No design is worse than unshaped on any move.</p>"
    quick = " (quick run: fewer moves and evaluations; not the benchmark)" if s.get("quick") else ""
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>Arm study {html.escape(s['name'])}</title>
<style>body{{font-family:sans-serif;max-width:1100px;margin:2em auto;color:#222}}
table{{border-collapse:collapse;margin:1em 0}}td,th{{border:1px solid #bbb;padding:2px 8px;text-align:right}}
img{{max-width:100%}}.warn li{{color:#a00}}figcaption{{font-size:90%;color:#555}}</style></head><body>
<h1>Arm study {html.escape(s['name'])}{html.escape(quick)}</h1>
<p>Arm <b>{html.escape(s['arm'])}</b> ({html.escape(joints)}). Pick-and-place benchmark of {len(doc['moves'])} moves
(seed {s['seed']}), each link starting in the middle of its play; {html.escape(s['method'])} shapers;
clearance-aware command designed per move with {s['clearance_aware']['evaluations']} evaluations{flank_text(doc)}.
Residual: {html.escape(s['residual'])}.</p>
<h2>Tool-tip residual per design</h2>
{table(design_rows, ['design', 'Σ residual (mm)', 'removed', 'moves worse than unshaped', 'command mean / max (s)'])}
<h2>Where a design is worse than unshaped</h2>
{warn_html}
{''.join(embedded(p, alt) for p, alt in figures)}
<h2>Mode map</h2>
<p>The map holds the <b>linearised</b> modes (arm::joint_modes: every play closed on a flank) at
{len(doc['mode_map']['poses'])} poses, not modes identified from runs. Lowest mode {f.min():.1f}–{f.max():.1f} Hz.</p>
<h2>Per move (mm)</h2>
{table(move_rows, ['move', 'end pose (rad)'] + names)}
</body></html>
"""


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 1 or argv[0] in ("-h", "--help"):
        print("usage: render_arm_study.py <arm-study-output-folder>", file=sys.stderr)
        return 2
    out = Path(argv[0])
    try:
        doc = read_results(out)
    except SystemExit as e:
        print(e, file=sys.stderr)
        return 2
    use_style()
    fig_dir = out / "figures"
    figures = [(fig_dir / "residual.png", "Tool-tip residual summed over the moves, per design (mm, % removed)"),
               (fig_dir / "mode-map.png", "Lowest linearised mode over the joint grid and over the workspace, "
                                          "arm drawn at the workspace centre"),
               (fig_dir / "improvement.png", "Improvement per move at its end pose, per design (crosses: worse "
                                             "than unshaped)")]
    residual_figure(doc, figures[0][0])
    mode_map_figure(doc, figures[1][0])
    improvement_figure(doc, figures[2][0])
    path = out / "report.html"
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(report(doc, figures), encoding="utf-8")
    tmp.replace(path)
    print(path.resolve())
    return 0


if __name__ == "__main__":
    sys.exit(main())
