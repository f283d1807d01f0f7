"""Draws the study's figures from its figure index (figures.json) in the clearshape style.

A figure entry (docs/study-outputs.md) names its id, kind, title, thesis figure number, one data
file (CSV under <out>/data/), the x column and label, the y label and its series (a column and a
label each). A series may also carry its own file, role or panel; an entry may have "panels".
Kinds:
  time-series    every series as a line, coloured by its role, which is read from the column name
                 (…_none = without shaping, …_zvdd@link-mode = ZVDD for the link mode, command_…,
                 measured/gyro, model/fitted, runNN_… = repeated trials). Trials draw thin in a
                 sequential palette, with their mean; a figure of repeated runs only gets a second
                 panel with each run minus the mean and its Eq. 4.1 error. "mean_deviation" annotations (per column key:
                 steady_mean, start_time_s, mean_deviation, start_rule) mark where Eq. 5.1's
                 steady state starts (circle: first crossing of M, diamond: entry into the ±b band)
                 and add MD to the legend; a series with role "command" is the reference input.
  sensitivity    residual vibration against frequency ratio, per shaper, in % with the 5 % line,
                 one small panel per shaper (its mode-source variants together) when several;
                 series with variant "designed" (the shaper before the update grid) thin and
                 dotted; "markers" [{x, label}] draw vertical lines (default: design frequency at 1).
  mean-deviation one response with its steady-state mean M, the start of the steady state, the
                 start band ±b and the ±MD band (Eq. 5.1, Fig. 5.9); MD is computed from M and the
                 start when not given.
  md-summary     (drawn by the report, from results.json) Eq. 5.1 means and improvements of every
                 trial table beside the thesis's.
Legends sit in a strip above the axes (or under the panels), never on the data.
Outputs: <id>.png (150 dpi) and <id>.pdf with fixed metadata: the same inputs give the same bytes.
"""
from __future__ import annotations

import json
import math
import re
import textwrap
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from . import roles  # noqa: E402
from .data import CsvCache, StudyDataError  # noqa: E402
from .tables import plain_label  # noqa: E402

STYLE_PATH = Path(__file__).with_name("clearshape.mplstyle")
LINE_KINDS = {"time-series", "timeseries", "lines", "repeat", "compare", "shaped", "commands", "psd"}

PNG_METADATA = {"Software": None}
PDF_METADATA = {"CreationDate": None, "ModDate": None, "Creator": "clearshape", "Producer": None}


def use_style() -> None:
    """Applies the clearshape style (call once before drawing)."""
    plt.style.use(str(STYLE_PATH))


def figure_id(spec: dict, index: int) -> str:
    raw = str(spec.get("id") or spec.get("name") or f"figure_{index + 1:02d}")
    return "".join(ch if ch.isalnum() or ch in "-_." else "_" for ch in raw)


def panels_of(spec: dict) -> list[dict]:
    """The entry's panels; an entry with figure-level series is one panel. Panel fields fall back
    to the entry's (file, x, y_label, ...)."""
    base = {k: v for k, v in spec.items() if k not in ("panels", "title", "id", "kind")}
    if spec.get("panels"):
        return [base | p for p in spec["panels"]]
    return [base]


def _x_column(panel: dict, s: dict) -> str:
    x = s.get("x") or panel.get("x")
    if isinstance(x, dict):
        return x.get("column") or "time_s"
    return x or "time_s"


def _y_column(s: dict) -> str:
    col = s.get("column") or s.get("y")
    if not col:
        raise StudyDataError(f"series {s} names no column")
    return col


def _file(panel: dict, s: dict) -> str:
    f = s.get("file") or panel.get("file")
    if not f:
        raise StudyDataError(f"series '{_y_column(s)}' names no data file")
    return f


def _x_label(panel: dict, xcol: str) -> str:
    x = panel.get("x")
    text = x.get("label") if isinstance(x, dict) else panel.get("x_label")
    return roles.label_with_unit(text, xcol)


def _y_label(panel: dict, ycol: str) -> str:
    y = panel.get("y")
    text = panel.get("y_label") or (y.get("label") if isinstance(y, dict) else None)
    if isinstance(y, dict) and y.get("unit") and text and "(" not in text:
        text = f"{text} ({y['unit']})"
    return roles.label_with_unit(text, ycol)


def _unit_of(label: str) -> str:
    return label.rsplit("(", 1)[-1].rstrip(")") if label.endswith(")") else ""


def _annotation(panel: dict, ycol: str) -> dict | None:
    ann = panel.get("mean_deviation")
    if not isinstance(ann, dict):
        return None
    if all(k in ann for k in ("steady_mean", "start_time_s")):
        return ann
    best = None
    for key, a in ann.items():
        if isinstance(a, dict) and ycol.endswith(key) and (best is None or len(key) > len(best[0])):
            best = (key, a)
    return best[1] if best else None


# How the Eq. 5.1 start was decided (metrics::StartRule) → marker and legend text.
START_MARKERS = {"crossing": "o", "band-entry": "D", "window-start": "s"}
START_RULE_TEXT = {"crossing": "first crossing of M", "band-entry": "enters ±b around M",
                   "window-start": "never meets M: final window"}


def _draw_lines(ax, panel: dict, cache: CsvCache, kind: str, deviation_ax=None) -> None:
    series = panel.get("series") or []
    if not series:
        raise StudyDataError("figure has no series")
    resolved = []
    for s in series:
        ycol = _y_column(s)
        role, source = roles.infer_role(ycol, s.get("label"))
        if s.get("role"):
            role = roles.normalise_role(s["role"])
        resolved.append((s, ycol, role, source))
    trials = [r for r in resolved if r[2] == "trial"]
    trial_colours = plt.get_cmap("viridis")(np.linspace(0.1, 0.85, max(len(trials), 1)))
    ylab = _y_label(panel, resolved[0][1])
    unit = _unit_of(ylab)
    trial_values = []
    other_index = 0
    marked: set = set()
    rules_seen: set = set()
    for s, ycol, role, source in resolved:
        f = _file(panel, s)
        x = cache.column(f, _x_column(panel, s))
        y = cache.column(f, ycol) * float(s.get("scale", 1.0))
        label = plain_label(s.get("label") or roles.label_for(role) or roles.quantity_from_column(ycol))
        if role == "trial":
            i = len(trial_values)
            style = {"color": trial_colours[i], "linestyle": "-", "linewidth": 0.8, "zorder": 2}
            label = (f"runs 1–{len(trials)}" if len(trials) > 1 else label) if i == 0 else None
            trial_values.append((x, y))
        else:
            style = roles.style_for(role, other_index, source)
            if not role:
                other_index += 1
        ann = None if role in ("command", "shaped_command") else _annotation(panel, ycol)
        if ann and label:
            md = ann.get("mean_deviation")
            if md is not None:
                start = ann.get("start_time_s")
                label = f"{label} — MD {md:.3g} {unit}".rstrip() + (f" from {float(start):.3g} s" if start is not None
                                                                      else "")
        ax.plot(x, y, label=label, **style)
        if ann and ann.get("start_time_s") is not None and float(ann["start_time_s"]) not in marked:
            t0 = float(ann["start_time_s"])
            marked.add(t0)  # a later series starting at the same sample would hide this marker
            k = min(int(np.searchsorted(x, t0)), len(x) - 1)
            rule = ann.get("start_rule", "crossing")
            rules_seen.add(rule)
            ax.plot([x[k]], [y[k]], marker=START_MARKERS.get(rule, "o"), markersize=4.5, color=style["color"],
                    markeredgecolor="white", markeredgewidth=0.6, linestyle="none", zorder=8)
            if ann.get("steady_mean") is not None:
                ax.hlines(float(ann["steady_mean"]), x[k], x[-1], colors=style["color"], linewidth=0.7,
                          linestyles=(0, (1, 1.5)), alpha=0.8, zorder=1)
    if len(trial_values) > 1:
        n = min(len(v[1]) for v in trial_values)
        mean = np.mean([v[1][:n] for v in trial_values], axis=0)
        ax.plot(trial_values[0][0][:n], mean, label=f"mean of {len(trial_values)} runs", **roles.style_for("mean"))
        if deviation_ax is not None:
            _draw_deviations(deviation_ax, trial_values, trial_colours, unit)
    if panel.get("autozoom", True) and not panel.get("xlim"):
        window = _active_window([(cache.column(_file(panel, s), _x_column(panel, s)), cache.column(_file(panel, s), yc))
                                 for s, yc, _, _ in resolved])
        if window:
            ax.set_xlim(*window)
    for rule in [r for r in START_MARKERS if r in rules_seen]:
        ax.plot([], [], marker=START_MARKERS.get(rule, "o"), markersize=4.5, color="#555555", linestyle="none",
                label=f"Eq. 5.1 steady-state start ({START_RULE_TEXT.get(rule, rule)})")
    if kind == "psd" or panel.get("logy"):
        ax.set_yscale("log")
    if panel.get("logx"):
        ax.set_xscale("log")
    ax.set_xlabel(_x_label(panel, _x_column(panel, resolved[0][0])))
    ax.set_ylabel(ylab)


def eq_4_1(runs: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray, float]:
    """Eq. 4.1 (thesis §4.1.1, metrics/consistency.hpp): E_i = RMS_j(m_j − t_ij) / r with m the mean
    of the runs and r = max m − min m. Returns (E per run, m, r)."""
    n = min(len(r) for r in runs)
    y = np.array([r[:n] for r in runs], dtype=float)
    m = y.mean(axis=0)
    rng = float(m.max() - m.min())
    e = np.sqrt(np.mean((m - y) ** 2, axis=1)) / rng if rng > 0 else np.full(len(runs), np.nan)
    return e, m, rng


def trial_panel(panel: dict) -> bool:
    """A panel of repeated runs (every series a trial, at least 3): drawn with its deviation panel."""
    series = panel.get("series") or []
    if len(series) < 3:
        return False
    return all(roles.infer_role(_y_column(s), s.get("label"))[0] == "trial" for s in series)


def model_record_pair(panel: dict) -> tuple[dict, dict] | None:
    """(record, model) of a model-vs-record overlay: a panel of exactly two series, one measured
    (experiment, gyro, encoder) and one model (model, fitted, simulated); None otherwise."""
    series = panel.get("series") or []
    if len(series) != 2:
        return None
    found = {}
    for s in series:
        role = roles.normalise_role(s["role"]) if s.get("role") else roles.infer_role(_y_column(s), s.get("label"))[0]
        found.setdefault(role, s)
    return (found["measured"], found["model"]) if set(found) == {"measured", "model"} else None


def model_residual(panel: dict, cache: CsvCache) -> tuple[np.ndarray, np.ndarray]:
    """(time, record − model) on the record's samples; the model is interpolated when on another grid."""
    rec, mod = model_record_pair(panel)
    x = cache.column(_file(panel, rec), _x_column(panel, rec))
    y = cache.column(_file(panel, rec), _y_column(rec)) * float(rec.get("scale", 1.0))
    xm = cache.column(_file(panel, mod), _x_column(panel, mod))
    ym = cache.column(_file(panel, mod), _y_column(mod)) * float(mod.get("scale", 1.0))
    same = len(xm) == len(x) and np.array_equal(xm, x)
    return x, y - (ym if same else np.interp(x, xm, ym))


def _draw_model_residual(ax, panel: dict, cache: CsvCache, unit: str) -> None:
    """The panel under a model-vs-record overlay (as MATLAB's compare): record − model, with its RMS
    over the record, where a fit that looks perfect at the overlay's scale still misses."""
    x, r = model_residual(panel, cache)
    rms = float(np.sqrt(np.mean(r ** 2)))
    ax.plot(x, r, label="_residual", **roles.style_for("measured"))
    ax.axhline(0.0, color="#1a1a1a", linewidth=0.6, zorder=1)
    ax.set_ylabel(f"residual ({unit or '–'})")
    ax.set_title(f"Residual: record − model, RMS {rms:.3g} {unit}".rstrip(), fontweight="normal", fontsize=8.5)


def _draw_deviations(ax, trial_values, colours, unit: str) -> None:
    """Each run minus the mean of the runs, in % of the mean's range r, labelled with its Eq. 4.1
    error: the spread that Tables 4.1–4.2 measure, which the runs themselves hide by overlapping."""
    e, m, rng = eq_4_1([v[1] for v in trial_values])
    n = len(m)
    x = trial_values[0][0][:n]
    for i, (_, y) in enumerate(trial_values):
        ax.plot(x, 100.0 * (y[:n] - m) / rng, color=colours[i], linewidth=0.7,
                label=f"run {i + 1}: E = {e[i]:.2e}".replace("e-0", "e-"), zorder=2)
    ax.axhline(0.0, color="#1a1a1a", linewidth=0.6, zorder=1)
    ax.set_ylabel("run − mean (% of r)")
    ax.set_title(f"Deviation from the mean; Eq. 4.1 error E per run (r = {rng:.3g} {unit})".replace(" )", ")"),
                 fontweight="normal", fontsize=8.5)


def _active_window(curves, threshold: float = 0.006, margin: float = 0.5):
    """Time window where something happens: from the first departure of any curve from its initial
    value to the last time any curve is away from its final value by more than `threshold` of its
    range, widened by `margin` of that span. None when that is most of the record anyway (e.g. noisy
    or periodic signals), so the full record is shown."""
    t_lo, t_hi, t0, t1 = math.inf, -math.inf, math.inf, -math.inf
    for x, y in curves:
        if len(x) < 3:
            return None
        t0, t1 = min(t0, float(x[0])), max(t1, float(x[-1]))
        span = float(np.nanmax(y) - np.nanmin(y))
        if not math.isfinite(span) or span == 0:
            continue
        tail = max(1, len(y) // 50)
        moved = np.flatnonzero(np.abs(y - y[0]) > threshold * span)
        away = np.flatnonzero(np.abs(y - np.mean(y[-tail:])) > threshold * span)
        # A slow drift (an integrated gyro's) keeps a curve away from its final value to the end of the
        # record although nothing happens: what happens is what departs from its own running mean.
        k = max(3, len(y) // 25) | 1
        smooth = np.convolve(np.pad(y, k // 2, mode="edge"), np.ones(k) / k, mode="valid")
        resid = y - smooth
        late = resid[-max(3, len(y) // 3):]
        noise = 1.4826 * float(np.median(np.abs(late - np.median(late))))  # the sensor's noise, robustly
        busy = np.flatnonzero(np.abs(resid) > max(threshold * span, 5.0 * noise))
        if len(moved):
            t_lo = min(t_lo, float(x[moved[0]]))
        if len(away):
            last = away[-1] if not len(busy) else min(away[-1], busy[-1] + k)
            t_hi = max(t_hi, float(x[min(last, len(x) - 1)]))
    if not (math.isfinite(t_lo) and math.isfinite(t_hi)) or t_hi <= t_lo:
        return None
    pad = margin * (t_hi - t_lo)
    lo, hi = max(t0, t_lo - pad), min(t1, t_hi + pad)
    if hi - lo > 0.7 * (t1 - t0):
        return None
    return lo, hi


def sensitivity_groups(series: list[dict]) -> list[tuple[str, list[dict]]]:
    """The sensitivity series grouped by shaper (ZV, ZVD, ...), in the shapers' usual order: one
    small panel each, holding that shaper's variants (mode source, designed/applied)."""
    groups: dict[str, list[dict]] = {}
    for s in series:
        role, _ = roles.infer_role(_y_column(s).removesuffix("_designed"))
        groups.setdefault(roles.normalise_role(role) or _y_column(s), []).append(s)
    order = {r: i for i, r in enumerate(roles.SHAPER_ORDER)}
    return sorted(groups.items(), key=lambda kv: (order.get(kv[0], len(order)), kv[0]))


def _draw_sensitivity(ax, panel: dict, cache: CsvCache, title: str | None = None, legend_lines: bool = True) -> None:
    """Residual vibration V(ω/ωm) (Eq. 2.19) per shaper; fractions are shown in %."""
    series = panel.get("series") or []
    if not series:
        raise StudyDataError("sensitivity figure has no series")
    ys = []
    for s in series:
        f = _file(panel, s)
        ys.append((s, cache.column(f, _x_column(panel, s)), cache.column(f, _y_column(s))))
    as_fraction = panel.get("as_fraction")
    if as_fraction is None:
        as_fraction = max(float(np.nanmax(y)) for _, _, y in ys) <= 1.0 + 1e-9
    scale = 100.0 if as_fraction else 1.0
    for i, (s, x, y) in enumerate(ys):
        role, source = roles.infer_role(_y_column(s).removesuffix("_designed"))
        style = roles.style_for(role, i, source)
        if s.get("variant") == "designed":  # the shaper before the drive's update grid: thin, dotted
            style.update(linestyle=(0, (1, 1.2)), linewidth=1.0, alpha=0.9, zorder=2)
        label = s.get("label") or roles.label_for(role)
        if title:  # in a small panel the shaper is the title; the legend says the variant
            label = _variant_label(s, source)
        ax.plot(x, y * scale, label=label, **style)
    if title:
        ax.set_title(title, fontsize=9, fontweight="bold")
    tol = panel.get("tolerance_percent", 5.0)
    ax.axhline(float(tol), color="#7A7A7A", linestyle=":", linewidth=1.0,
               label=f"{tol:g} % (usual tolerance)" if legend_lines else None)
    markers = panel.get("markers") or [{"x": panel.get("design_x", 1.0), "label": "design frequency"}]
    for i, mk in enumerate(markers):
        ax.axvline(float(mk["x"]), color="#1a1a1a" if i == 0 else "#7A7A7A", linewidth=0.8,
                   linestyle=(0, (2, 2)) if i == 0 else (0, (6, 2, 1, 2)),
                   label=mk.get("label") if legend_lines else None)
    ax.set_ylim(bottom=0)
    ax.set_xlabel(_x_label(panel, _x_column(panel, series[0])))
    text = panel.get("y_label") or "residual vibration"
    text = text.split("(")[0].strip()
    ax.set_ylabel(f"{text} (%)" if as_fraction else roles.label_with_unit(panel.get("y_label"), _y_column(series[0])))


def _variant_label(s: dict, source: str) -> str:
    mode = {"link-mode": "link mode", "drive-model": "drive model"}.get(source, source or "")
    text = f"designed for the {mode}" if mode else "as designed"
    if s.get("variant") == "designed":
        return text + " (before the update grid)"
    return text


def _draw_sensitivity_multiples(fig, spec: dict, cache: CsvCache) -> None:
    """One small panel per shaper (2 columns), the same axes in each, one legend under the grid."""
    panel = panels_of(spec)[0]
    groups = sensitivity_groups(panel.get("series") or [])
    if not groups:
        raise StudyDataError("sensitivity figure has no series")
    ncols = 2 if len(groups) > 1 else 1
    nrows = math.ceil(len(groups) / ncols)
    fig.set_size_inches(7.6, 1.0 + 1.75 * nrows)
    axes = fig.subplots(nrows, ncols, squeeze=False, sharex=True, sharey=True)
    flat = list(axes.ravel())
    first_values = [cache.column(_file(panel, s), _y_column(s)) for s in panel["series"]]
    as_fraction = max(float(np.nanmax(y)) for y in first_values) <= 1.0 + 1e-9
    for k, (role, series) in enumerate(groups):
        sub = dict(panel, series=series, as_fraction=as_fraction)
        _draw_sensitivity(flat[k], sub, cache, title=roles.label_for(role), legend_lines=(k == 0))
        if k % ncols:
            flat[k].set_ylabel("")
        if k < len(groups) - ncols:
            flat[k].set_xlabel("")
        else:  # the lowest panel of its column shows the frequency ratio's ticks
            flat[k].xaxis.set_tick_params(labelbottom=True)
    for ax in flat[len(groups):]:
        ax.set_visible(False)
    # One legend for every panel: the variants' line styles and the reference lines, taken from
    # the panels (the first panel carries the reference lines), below the grid.
    seen, handles, labels = set(), [], []
    for ax in flat[:len(groups)]:
        for h, lab in zip(*ax.get_legend_handles_labels()):
            if lab not in seen:
                seen.add(lab)
                handles.append(h)
                labels.append(lab)
    target = flat[len(groups) - 1] if len(groups) % ncols == 0 else flat[len(groups)]
    if target.get_visible():
        target.legend(handles, labels, loc="upper left", bbox_to_anchor=(0.0, -0.35), ncol=2, fontsize=7.5)
    else:
        target.set_visible(True)
        target.axis("off")
        target.legend(handles, labels, loc="center", fontsize=7.5, frameon=False)


def eq_5_1(t: np.ndarray, s: np.ndarray, final_window_fraction: float = 0.2,
           search_from_s: float = -math.inf, max_iterations: int = 100, band_noise_multiple: float = 0.0,
           band_move_fraction: float = 0.005, band_dwell_s: float = 0.1, band_half_width: float | None = None) -> dict:
    """Eq. 5.1 with the steady-state start of §5.1.2 as metrics::mean_deviation computes it
    (include/clearshape/metrics/mean_deviation.hpp): after the response has departed from M (half
    its largest excursion), the start is the earlier of the first crossing of M and the first stay
    of band_dwell_s inside ±b around M, M and the start iterated to a fixed point. Returns mean_deviation, steady_mean, start_index, start_rule, band_half_width."""
    s = np.asarray(s, dtype=float)
    n = len(s)
    ts = float(t[1] - t[0]) if n > 1 else 1.0
    first = 0
    if search_from_s > float(t[0]):
        first = min(int(math.ceil((search_from_s - float(t[0])) / ts - 1e-9)), n - 1)
    window_start = max(first, n - min(max(int(math.ceil(final_window_fraction * n)), 1), n))
    m = float(np.mean(s[window_start:]))
    tail = s[window_start:]
    sigma = float(np.sqrt(np.sum(np.diff(tail) ** 2) / (2 * (tail.size - 1)))) if tail.size > 1 else 0.0
    band = (max(band_noise_multiple * sigma, band_move_fraction * abs(m - float(s[first])))
            if band_half_width is None else float(band_half_width))
    dwell = max(1, int(round(band_dwell_s / ts)))

    def meet(mean: float):
        d = s[first:] - mean
        big = float(np.max(np.abs(d))) if d.size else 0.0
        if not big > 0:
            return None
        # Departure: the steady state is looked for only after the response has left M, i.e. from
        # the first sample at half its largest excursion (a rest on M before the move is no start).
        j = int(np.flatnonzero(np.abs(d) >= 0.5 * big)[0])
        d = d[j:]
        hit = d == 0.0
        hit[1:] |= np.sign(d[1:]) * np.sign(d[:-1]) < 0
        cross = np.flatnonzero(hit)
        c = int(cross[0]) if cross.size else None
        e = None
        if band > 0:
            inside = np.concatenate([[0], (np.abs(d) <= band).astype(np.int8), [0]])
            edges = np.diff(inside)
            starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
            ok = (ends - starts >= dwell) | (ends == d.size)
            e = int(starts[ok][0]) if ok.any() else None
        if e is not None and (c is None or e < c):
            return first + j + e, "band-entry"
        return (first + j + c, "crossing") if c is not None else None

    got = meet(m)
    k, rule = got if got else (window_start, "window-start")
    seen = [k]
    for _ in range(max_iterations):
        m = float(np.mean(s[k:]))
        got = meet(m)
        k_new, rule_new = got if got else (k, rule)
        if k_new == k:
            rule = rule_new
            break
        if k_new in seen:
            k, rule = k_new, rule_new
            m = float(np.mean(s[k:]))
            break
        k, rule = k_new, rule_new
        seen.append(k)
    md = float(np.sqrt(np.mean((m - s[k:]) ** 2)))
    return {"mean_deviation": md, "steady_mean": m, "start_index": k, "start_rule": rule,
            "band_half_width": band}


def steady_state_mean_deviation(t: np.ndarray, s: np.ndarray, final_window_fraction: float = 0.2,
                                 search_from_s: float = -math.inf, max_iterations: int = 100):
    """Eq. 5.1 (eq_5_1 with the default band). Returns (MD, M, start index)."""
    r = eq_5_1(t, s, final_window_fraction, search_from_s, max_iterations)
    return r["mean_deviation"], r["steady_mean"], r["start_index"]


def _mean_deviation_inputs(panel: dict, cache: CsvCache) -> dict:
    """The response of a mean-deviation panel with Eq. 5.1's M, start (index k and time), MD, start rule
    and band, as the study gives them or, where it does not, from eq_5_1."""
    s = (panel.get("series") or [None])[0]
    if s is None:
        raise StudyDataError("mean-deviation figure has no series")
    f = _file(panel, s)
    t = cache.column(f, _x_column(panel, s))
    y = cache.column(f, _y_column(s))
    mean, start_s, md = panel.get("steady_mean"), panel.get("start_time_s"), panel.get("mean_deviation")
    if isinstance(md, dict):
        md = None
    rule, band = panel.get("start_rule"), panel.get("band_half_width")
    if mean is None or start_s is None:
        r = eq_5_1(t, y)
        mean = r["steady_mean"] if mean is None else mean
        start_s = float(t[r["start_index"]]) if start_s is None else start_s
        rule = rule or r["start_rule"]
        band = r["band_half_width"] if band is None else band
    k = int(np.searchsorted(t, float(start_s)))
    if md is None:  # Eq. 5.1 from the given M and start
        md = float(np.sqrt(np.mean((float(mean) - y[k:]) ** 2)))
    return {"series": s, "t": t, "y": y, "mean": float(mean), "start_s": float(start_s), "k": k, "md": float(md),
            "rule": rule, "band": band}


def steady_drift(t: np.ndarray, y: np.ndarray, k: int) -> dict | None:
    """The steady state's slow drift, reported apart from Eq. 5.1 (an integrated gyro's bias makes the
    link angle wander): the least-squares line through y[k:], its slope, the change it makes over the
    steady state, and the RMS about that line (Eq. 5.1 with the line in place of M). None under 3 samples."""
    if len(y) - k < 3:
        return None
    tt, yy = t[k:] - t[k], y[k:]
    slope, offset = np.polyfit(tt, yy, 1)
    line = slope * tt + offset
    return {"slope": float(slope), "change": float(slope * tt[-1]), "t": t[k:], "line": line,
            "md_about_line": float(np.sqrt(np.mean((yy - line) ** 2)))}


def _minus_signs(text: str) -> str:
    """A number's sign as the typographic minus (U+2212), as the tables print it; hyphens in words stay."""
    return re.sub(r"-(?=[0-9.])", "\u2212", text)


def drift_caption(panel: dict, cache: CsvCache) -> str:
    """The figure caption's account of the drift: reported apart, not removed, with its share of MD²."""
    m = _mean_deviation_inputs(panel, cache)
    d = steady_drift(m["t"], m["y"], m["k"])
    if d is None:
        return ""
    unit = _unit_of(_y_label(panel, _y_column(m["series"])))
    share = max(0.0, 1.0 - (d["md_about_line"] / m["md"]) ** 2) if m["md"] > 0 else 0.0
    return _minus_signs(
        f"Drift reported apart, not removed: the steady state drifts by {d['change']:+.3g} {unit} "
        f"({d['slope']:+.3g} {unit}/s, a least-squares line, as an integrated gyro's bias would make the angle "
        f"wander); MD = {m['md']:.3g} {unit} includes it as the tables do ({100 * share:.0f} % of MD² is the "
        f"drift); about the drift line the RMS is {d['md_about_line']:.3g} {unit}")


def _draw_mean_deviation(ax, panel: dict, cache: CsvCache) -> None:
    m = _mean_deviation_inputs(panel, cache)
    s, t, y, mean, start_s, k, md = (m[x] for x in ("series", "t", "y", "mean", "start_s", "k", "md"))
    rule, band = m["rule"], m["band"]
    ylab = _y_label(panel, _y_column(s))
    unit = _unit_of(ylab)
    ax.axvspan(float(start_s), float(t[-1]), color="#F2F2F2", zorder=0, linewidth=0,
               label="steady state (enters Eq. 5.1)")
    ax.axhspan(mean - md, mean + md, color=roles.style_for("mean")["color"], alpha=0.13, linewidth=0,
               label=f"M ± MD, MD = {md:.3g} {unit}")
    role, source = roles.infer_role(_y_column(s))  # md_signal_zvdd@link-mode → the ZVDD colour
    label = plain_label(s.get("label") or "response")
    if role in roles.SHAPER_LABELS and roles.SHAPER_LABELS[role].lower() not in label.lower():
        label = f"{label} ({roles.SHAPER_LABELS[role]})"  # the design its colour stands for
    ax.plot(t, y, label=label, **roles.style_for(role or "unshaped", 0, source))
    ax.axhline(mean, label=f"steady-state mean M = {mean:.4g} {unit}", **roles.style_for("mean"))
    if band:
        ax.axhline(mean - float(band), color="#7A7A7A", linewidth=0.7, linestyle=":",
                   label=f"M ± b, b = {float(band):.3g} {unit} (start band)")
        ax.axhline(mean + float(band), color="#7A7A7A", linewidth=0.7, linestyle=":")
    drift = steady_drift(t, y, k)
    if drift is not None:
        ax.plot(drift["t"], drift["line"], color="#1a1a1a", linewidth=0.9, linestyle=(0, (3, 1, 1, 1)), zorder=6,
                label=_minus_signs(f"drift {drift['slope']:+.2g} {unit}/s (reported apart; RMS about it "
                                   f"{drift['md_about_line']:.3g} {unit})"))
    rule = rule or "crossing"
    ax.plot([t[min(k, len(t) - 1)]], [y[min(k, len(t) - 1)]], marker=START_MARKERS.get(rule, "o"), markersize=5,
            color="#1a1a1a", linestyle="none", zorder=9,
            label=f"{START_RULE_TEXT.get(rule, rule)}, t = {float(start_s):.3f} s")
    ax.set_xlabel(_x_label(panel, _x_column(panel, s)))
    ax.set_ylabel(ylab)
    # Zoom on the response around its final value so the ringing is visible.
    lo, hi = float(np.min(y[k:])), float(np.max(y[k:]))
    pad = max(hi - lo, 4 * md, 1e-9)
    full_lo, full_hi = float(np.min(y)), float(np.max(y))
    if full_hi - full_lo > 8 * pad:
        ax.set_ylim(lo - pad, hi + pad)
        t_lo = max(float(t[0]), float(start_s) - 0.25 * (float(t[-1]) - float(start_s)))
        ax.set_xlim(t_lo, float(t[-1]))
    else:  # the whole move in view, in time only where the response still moves
        window = _active_window([(t, y)])
        if window:
            ax.set_xlim(window[0], max(window[1], float(start_s) + 0.1 * (float(t[-1]) - float(t[0]))))
        _md_band_inset(ax, m, unit)


# The ±MD band is drawn at least this share of an axis's height; below it (0.8° on a 25° move) a
# zoomed inset shows the steady state around M at ±MD_INSET_HALF_SPAN_MD × MD.
MD_BAND_MIN_SHARE = 0.06
MD_INSET_HALF_SPAN_MD = 4.0


def _md_band_inset(ax, m: dict, unit: str) -> None:
    """A zoomed inset of the steady state around M where the whole move leaves the ±MD band too thin to
    see, placed on the side of the axes the move started from (the response's rest level)."""
    mean, md, t, y, start_s = m["mean"], m["md"], m["t"], m["y"], m["start_s"]
    y_lo, y_hi = ax.get_ylim()
    if md <= 0 or 2 * md >= MD_BAND_MIN_SHARE * (y_hi - y_lo):
        return
    below = float(y[0]) < mean  # a move up: the lower half is empty after the start
    ins = ax.inset_axes([0.42, 0.06 if below else 0.5, 0.55, 0.42])
    ins.axhspan(mean - md, mean + md, color=roles.style_for("mean")["color"], alpha=0.13, linewidth=0, label="_M ± MD")
    role, source = roles.infer_role(_y_column(m["series"]))
    ins.plot(t, y, **roles.style_for(role or "unshaped", 0, source))
    ins.axhline(mean, **roles.style_for("mean"))
    half = MD_INSET_HALF_SPAN_MD * md
    ins.set_ylim(mean - half, mean + half)
    ins.set_xlim(float(start_s), min(float(t[-1]), ax.get_xlim()[1]))
    ins.set_title(f"steady state zoomed: M ± {MD_INSET_HALF_SPAN_MD:g} MD (± {half:.3g} {unit})",
                  fontsize=7, pad=2)
    ins.tick_params(labelsize=6, length=2, pad=1)
    ins.set_facecolor("white")
    ax.indicate_inset_zoom(ins, edgecolor="#7A7A7A", alpha=0.8)


# "Without shaping" bars: a neutral dark grey that no shaper uses, so no shaped bar can be
# mistaken for an unshaped one (ZVD's orange sits next to the unshaped vermillion).
WITHOUT_BAR_COLOUR = "#4D4D4D"
# A result worse than unshaped (the report's --worse colour): cross-hatched bars and their label.
WORSE_COLOUR = "#B3003C"
# Bars of a result worse than unshaped are cross-hatched (matplotlib hatch pattern: dense crosses),
# so they read as "worse" in greyscale print too, not by colour alone.
WORSE_HATCH = "xxx"


def _sample_sd(values) -> float | None:
    v = [float(x) for x in values or [] if isinstance(x, (int, float))]
    return float(np.std(v, ddof=1)) if len(v) > 1 else None


def with_trial_spreads(spec: dict, results: dict) -> dict:
    """The summary spec with each bar's ±1 s.d. over its trials (ours_without_sd, thesis_with_sd, …), from
    the trial table the row names in results.json: the column whose trial mean is the bar's value."""
    tables = {t.get("id"): t for t in results.get("tables", []) or [] if isinstance(t, dict)}
    rows = []
    for r in spec.get("rows") or []:
        r = dict(r)
        for side in ("ours", "thesis"):
            for key in ("without", "with"):
                bar = r.get(f"{side}_{key}")
                for c in (tables.get(r.get("table")) or {}).get("columns", []):
                    vals = [x for x in c.get(side) or [] if isinstance(x, (int, float))]
                    # the thesis's printed mean is its trials' mean to its printed digits
                    tol = 1e-6 if side == "ours" else 0.02
                    if bar is not None and vals and math.isclose(sum(vals) / len(vals), bar, rel_tol=tol):
                        r[f"{side}_{key}_sd"] = _sample_sd(vals)
                        break
        rows.append(r)
    return {**spec, "rows": rows}


def summary_title(spec: dict) -> str:
    """The summary's title names each panel's quantity in its own unit (a "%" title stood over the
    degrees of the left panel): mean deviation in the study's unit, improvement in %."""
    unit = roles.pretty_unit(spec.get("unit") or "")
    table = f"Table {spec['thesis_table']}: " if spec.get("thesis_table") else ""
    return (f"{table}Eq. 5.1 mean deviation without and with shaping (left, {unit}, ±1 s.d.) and the "
            "improvement by shaping (right, %, 95 % bootstrap interval), clearshape beside the thesis")


def summary_slots(rows: list[dict], w: float):
    """Bar positions of the summary's left panel: (x, row, side, without/with) per bar and (x, label) per
    tick. Rows of one table (several shapers on one input, as the speed study's 5.1) share its unshaped
    pair, drawn once, then one pair per shaper labelled by the shaper; a table of one row keeps its four
    bars under the input's label."""
    slots, ticks, x = [], [], 0.0
    groups: dict = {}
    for i, r in enumerate(rows):
        groups.setdefault(r.get("table"), []).append(i)
    for members in groups.values():
        if len(members) == 1:
            i = members[0]
            slots += [(x + (j - 1.5) * w, i, side, key) for j, (side, key) in
                      enumerate((("ours", "without"), ("thesis", "without"), ("ours", "with"), ("thesis", "with")))]
            ticks.append((x, f"{wrap_tick(rows[i]['label'])}\n{rows[i].get('table')}" if rows[i].get("table")
                          else rows[i]["label"]))
            x += 1.0
            continue
        first = members[0]
        slots += [(x - 0.5 * w, first, "ours", "without"), (x + 0.5 * w, first, "thesis", "without")]
        ticks.append((x, f"without IS\n{rows[first].get('table')}"))
        for i in members:
            x += 2.6 * w
            slots += [(x - 0.5 * w, i, "ours", "with"), (x + 0.5 * w, i, "thesis", "with")]
            ticks.append((x, roles.label_for(rows[i].get("role")) or rows[i]["label"]))
        x += 1.0
    return slots, ticks


def wrap_tick(label: str, width: int = 12) -> str:
    """A tick label on lines of at most `width` characters, so neighbours never overlap."""
    return "\n".join(textwrap.wrap(label, width)) if "\n" not in label else label


def _draw_md_summary(axes, spec: dict) -> None:
    """Left: Eq. 5.1 means without/with shaping per table (ours solid, thesis hatched). Right:
    improvement % per table, ours beside the thesis's."""
    rows = spec.get("rows") or []
    if not rows:
        raise StudyDataError("md-summary has no rows")
    ax, ax2 = axes
    x = np.arange(len(rows))
    w = 0.2
    shaped_colours = [roles.style_for(roles.normalise_role(r.get("role") or "zvdd"))["color"] for r in rows]
    slots, ticks = summary_slots(rows, w)
    for j, (side, key) in enumerate((("ours", "without"), ("thesis", "without"), ("ours", "with"), ("thesis", "with"))):
        mine = [(pos, i) for pos, i, sd_, k in slots if (sd_, k) == (side, key)]
        vals = [rows[i].get(f"{side}_{key}") for _, i in mine]
        vals = [np.nan if v is None else v for v in vals]
        colours = [WITHOUT_BAR_COLOUR if key == "without" else shaped_colours[i] for _, i in mine]
        kw = ({"color": colours, "edgecolor": "#333333"} if side == "ours" else
              {"color": "white", "edgecolor": colours, "hatch": "////"})
        # ±1 s.d. over the trials; on the log axis the lower bar stops at a tenth of the mean
        sd = [rows[i].get(f"{side}_{key}_sd") for _, i in mine]
        err = np.array([[min(d, 0.9 * v), d] if d is not None and np.isfinite(v) else [np.nan, np.nan]
                        for d, v in zip(sd, vals)]).T
        ax.bar([pos for pos, _ in mine], vals, w, label=f"{'without' if key == 'without' else 'with'} shaping — "
               f"{'clearshape' if side == 'ours' else 'thesis'}", zorder=3, linewidth=0.8,
               yerr=err if np.isfinite(err).any() else None,
               error_kw={"ecolor": "#1a1a1a", "capsize": 1.8, "elinewidth": 0.7, "zorder": 4}, **kw)
    ax.set_xticks([t for t, _ in ticks], [wrap_tick(lab) for _, lab in ticks])
    ax.grid(axis="x", visible=False)
    ax.set_ylabel(roles.label_with_unit(f"mean deviation, Eq. 5.1 ({spec.get('unit', '')})"))
    values = [v for r in rows for v in (r.get("ours_without"), r.get("thesis_without"),
                                         r.get("ours_with"), r.get("thesis_with")) if v is not None and v > 0]
    tops = [r[f"{k}"] + (r.get(f"{k}_sd") or 0.0) for r in rows for k in ("ours_without", "thesis_without",
                                                                          "ours_with", "thesis_with")
            if r.get(k) is not None and r[k] > 0]
    top = max(tops)  # the highest bar with its error bar
    if min(values) < top / 10:  # shaped bars a tenth of the unshaped: a log axis keeps both readable
        ax.set_yscale("log")
        ax.set_ylim(min(values) / 2, 2 * top)
    else:
        ax.set_ylim(0, 1.1 * top)
    ax.legend(fontsize=7, loc="lower left", bbox_to_anchor=(0.0, 1.02), ncol=2, borderaxespad=0.0)
    ours = [np.nan if r.get("ours_improvement") is None else r["ours_improvement"] for r in rows]
    th = [np.nan if r.get("thesis_improvement") is None else r["thesis_improvement"] for r in rows]
    # Error bars: each improvement's 95 % bootstrap interval (results.json), where the study gives one.
    ci = [r.get("ours_improvement_ci95") if isinstance(r.get("ours_improvement_ci95"), list) else None for r in rows]
    err = np.array([[o - c[0], c[1] - o] if c and not np.isnan(o) else [np.nan, np.nan] for o, c in zip(ours, ci)]).T
    bars = ax2.bar(x - 0.18, ours, 0.36, color=shaped_colours, edgecolor="#333333", label="clearshape",
                   zorder=3, linewidth=0.8, yerr=err if np.isfinite(err).any() else None,
                   error_kw={"ecolor": "#1a1a1a", "capsize": 2.5, "elinewidth": 0.9, "zorder": 4})
    ax2.bar(x + 0.18, th, 0.36, label="thesis", zorder=3, linewidth=0.8, **roles.THESIS_BAR)
    shared = {r.get("table") for r in rows if sum(q.get("table") == r.get("table") for q in rows) > 1}
    # the narrower panel names each bar by its table (the left panel gives the input beside it) or, where
    # one table holds several shapers, by the shaper
    ax2.set_xticks(x, [roles.label_for(r.get("role")) if r.get("table") in shared else str(r.get("table") or r["label"])
                       for r in rows])
    ax2.grid(axis="x", visible=False)
    # The axis holds every bar and interval: an improvement below 0 (worse than unshaped) is drawn below
    # the zero line, cross-hatched in the worse colour and labelled, never cut off.
    lows = [v for v in ours + th if not np.isnan(v)] + [c[0] for c in ci if c]
    highs = [v for v in ours + th if not np.isnan(v)] + [c[1] for c in ci if c]
    lo = min([0.0] + lows)
    hi = max([100.0] + highs)
    pad = 0.08 * (hi - lo)
    ax2.set_ylim(lo - (pad if lo < 0 else 0), hi + 0.05 * (hi - lo))
    ax2.axhline(0.0, color="#1a1a1a", linewidth=0.8, zorder=5)
    for b, v in zip(bars, ours):
        if not np.isnan(v) and v < 0:
            b.set_hatch(WORSE_HATCH)
            b.set_edgecolor(WORSE_COLOUR)
            ax2.annotate("▼ worse than\nunshaped", (b.get_x() + b.get_width() / 2, v), xytext=(0, -3),
                         textcoords="offset points", ha="center", va="top", fontsize=6.5, color=WORSE_COLOUR,
                         zorder=6)
    if lo < 0:
        ax2.set_ylim(lo - 2.2 * pad, ax2.get_ylim()[1])
    ax2.set_ylabel("improvement by shaping (%)")
    ax2.legend(fontsize=7, loc="lower left", bbox_to_anchor=(0.0, 1.02), ncol=2, borderaxespad=0.0)


# Share of the figure's width the plot keeps beside its y label: a legend strip may be no wider.
LEGEND_STRIP_WIDTH = 0.86


def legend_strip(fig, ax, fontsize: float | None = None) -> None:
    """The axes' legend as a compact strip above its data, in as many columns (at most 4) as fit in the
    plot's width, measured; a panel title becomes the strip's title. The figure grows by the strip's
    height, so the plot keeps the figure's width instead of giving half of it to a legend."""
    _, labels = ax.get_legend_handles_labels()
    if not labels:
        return
    title = ax.get_title("left") or ax.get_title()  # the style puts titles on the left
    ax.set_title("", loc="left")
    ax.set_title("")
    renderer = fig.canvas.get_renderer()
    width_px = LEGEND_STRIP_WIDTH * fig.get_size_inches()[0] * fig.dpi
    for ncol in range(min(4, len(labels)), 0, -1):
        leg = ax.legend(loc="lower left", bbox_to_anchor=(0.0, 1.02), ncol=ncol, borderaxespad=0.0,
                        fontsize=fontsize, title=title or None, title_fontsize=8.5, alignment="left")
        box = leg.get_window_extent(renderer)
        if box.width <= width_px or ncol == 1:
            break
    w_in, h_in = fig.get_size_inches()
    fig.set_size_inches(w_in, h_in + box.height / fig.dpi)


def _new_figure(n_panels: int, spec: dict):
    rows, cols = (n_panels, 1) if n_panels <= 3 else (math.ceil(n_panels / 2), 2)
    width = 6.4 if cols == 1 else 7.6
    height = spec.get("height_in") or (3.1 if rows == 1 else 1.2 + 2.1 * rows)
    fig, axes = plt.subplots(rows, cols, figsize=(width, height), squeeze=False)
    flat = list(axes.ravel())
    for ax in flat[n_panels:]:
        ax.set_visible(False)
    return fig, flat[:n_panels]


def draw(spec: dict, cache: CsvCache, index: int = 0):
    """Builds the matplotlib Figure of one figure entry (raises StudyDataError on missing data)."""
    kind = str(spec.get("kind", "time-series")).lower()
    panels = panels_of(spec)
    if kind == "md-summary":
        spec = {**spec, "title": summary_title(spec)}
        fig, axes = plt.subplots(1, 2, figsize=(7.6, 3.6), gridspec_kw={"width_ratios": [3, 2]})
        _draw_md_summary(axes, spec)
        panels, axes = [], []
    elif kind == "sensitivity" and len(panels) == 1 and len(sensitivity_groups(panels[0].get("series") or [])) > 1:
        fig = plt.figure()
        _draw_sensitivity_multiples(fig, spec, cache)
        panels, axes = [], []
    elif kind in LINE_KINDS and len(panels) == 1 and trial_panel(panels[0]):
        fig, (ax, dev) = plt.subplots(2, 1, figsize=(8.2, 5.2), sharex=True, gridspec_kw={"height_ratios": [3, 2]})
        _draw_lines(ax, panels[0], cache, kind, deviation_ax=dev)
        ax.set_xlabel("")
        dev.set_xlabel(_x_label(panels[0], _x_column(panels[0], panels[0]["series"][0])))
        legend_strip(fig, ax)
        legend_strip(fig, dev, fontsize=7)
        panels, axes = [], []
    elif kind in LINE_KINDS and len(panels) == 1 and model_record_pair(panels[0]):
        fig, (ax, res) = plt.subplots(2, 1, figsize=(6.4, 4.4), sharex=True, gridspec_kw={"height_ratios": [3, 1.3]})
        _draw_lines(ax, panels[0], cache, kind)
        ax.set_xlabel("")
        _draw_model_residual(res, panels[0], cache, _unit_of(ax.get_ylabel()))
        res.set_xlabel(_x_label(panels[0], _x_column(panels[0], panels[0]["series"][0])))
        axes = [ax]
    else:
        fig, axes = _new_figure(len(panels), spec)
        for ax, panel in zip(axes, panels):
            if kind == "sensitivity":
                _draw_sensitivity(ax, panel, cache)
            elif kind in ("mean-deviation", "mean_deviation"):
                _draw_mean_deviation(ax, panel, cache)
            elif kind in LINE_KINDS:
                _draw_lines(ax, panel, cache, kind)
            else:
                raise StudyDataError(f"unknown figure kind '{kind}'")
    for ax, panel in zip(axes, panels):
        if panel.get("panel_title"):
            ax.set_title(panel["panel_title"], fontweight="normal", fontsize=9.5)
        if panel.get("xlim"):
            ax.set_xlim(*panel["xlim"])
        if panel.get("ylim"):
            ax.set_ylim(*panel["ylim"])
        legend_strip(fig, ax)
    num = spec.get("thesis_figure")
    head = (f"Fig. {num} analogue — " if num else "") + plain_label(str(spec.get("title") or spec.get("id") or ""))
    fig.suptitle("\n".join(textwrap.wrap(head, 92)[:2]), x=0.01, ha="left", fontsize=9, fontweight="normal",
                 color="#444444")
    return fig


def save(fig, out_dir: Path, fid: str) -> dict:
    """Writes <fid>.png and <fid>.pdf with fixed metadata; returns their paths."""
    out_dir.mkdir(parents=True, exist_ok=True)
    png = out_dir / f"{fid}.png"
    pdf = out_dir / f"{fid}.pdf"
    fig.savefig(png, dpi=150, metadata=PNG_METADATA)
    fig.savefig(pdf, metadata=PDF_METADATA)
    plt.close(fig)
    return {"png": png, "pdf": pdf}


def zoom_note(fig, spec: dict, cache: CsvCache) -> str:
    """The caption's note on a time axis zoomed to the move and its ringing (_active_window): which part of
    the record is drawn and where the whole record is, so no reader takes the window for the record."""
    if str(spec.get("kind", "time-series")).lower() not in LINE_KINDS or not fig.axes:
        return ""
    panel = panels_of(spec)[0]
    s = (panel.get("series") or [None])[0]
    if s is None or _x_column(panel, s) != "time_s":
        return ""
    x = cache.column(_file(panel, s), "time_s")
    lo, hi = fig.axes[0].get_xlim()
    if hi - lo >= 0.9 * (float(x[-1]) - float(x[0])):
        return ""
    return (f"Time axis zoomed to the move and its ringing: {lo:.2f}–{hi:.2f} s of the {float(x[0]):.3g}–"
            f"{float(x[-1]):.3g} s record (the whole record: {_file(panel, s)})")


def draw_all(study_dir: Path, specs: list[dict], out_dir: Path | None = None, log=print) -> list[dict]:
    """Draws every figure; one failed figure does not stop the others. Returns one record per
    figure: id, spec, png, pdf, error (None when drawn)."""
    use_style()
    study_dir = Path(study_dir)
    out_dir = Path(out_dir) if out_dir else study_dir / "figures"
    cache = CsvCache(study_dir)
    results_path = study_dir / "results.json"
    results = json.loads(results_path.read_text(encoding="utf-8")) if results_path.exists() else {}
    records = []
    for i, spec in enumerate(specs):
        if str(spec.get("kind")) == "md-summary":
            spec = with_trial_spreads(spec, results)
        fid = figure_id(spec, i)
        rec = {"id": fid, "spec": spec, "png": None, "pdf": None, "error": None}
        try:
            fig = draw(spec, cache, i)
            rec.update(save(fig, out_dir, fid))
            if str(spec.get("kind")) in ("mean-deviation", "mean_deviation"):
                rec["caption"] = drift_caption(panels_of(spec)[0], cache)
            else:
                rec["caption"] = zoom_note(fig, spec, cache)
        except (StudyDataError, KeyError, ValueError, TypeError, IndexError) as e:
            plt.close("all")
            msg = f"missing field {e}" if isinstance(e, KeyError) else str(e)
            rec["error"] = msg
            log(f"clearshape-plot: figure {fid}: {msg}")
        records.append(rec)
    return records
