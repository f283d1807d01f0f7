#!/usr/bin/python3
"""Writes <out>/report.html for a clearshape study output folder.

    /usr/bin/python3 python/make_report.py <out>

Reads <out>/results.json (tables with the thesis's numbers beside ours, the stages' sections,
settled ambiguities), <out>/figures.json and the PNGs in <out>/figures/ (python/render_study.py
draws them, then calls this). The page is self-contained — figures embedded as base64 PNG, inline
CSS, one small inline script, no network — and walks through the study in the thesis's order:
set-up, consistency, identification, clearance model, simulated tests, rig tests, ambiguities
settled, where we differ and why. Once the page has loaded (every <img> loaded or failed), the script sets
data-figures-loaded (images with naturalWidth > 0) and data-figures-failed on <body>.
"""
from __future__ import annotations

import base64
import dataclasses
import html
import json
import math
import re
import struct
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import jinja2  # noqa: E402
from markupsafe import Markup  # noqa: E402

from clearshape_plot import tables as tbl  # noqa: E402
from clearshape_plot.data import StudyDataError, read_json  # noqa: E402
from clearshape_plot.figures import figure_id  # noqa: E402
from clearshape_plot.roles import pretty_unit  # noqa: E402

SECTIONS = [
    ("setup", "Set-up", "What was run, on which rig, with which settings."),
    ("consistency", "Consistency of the responses",
     "Thesis §4.1: each input repeated, Eq. 4.1 error of every run against the mean of the runs "
     "(Tables 4.1, 4.2; Figures 4.2–4.8)."),
    ("identification", "Identification",
     "Thesis §4.2: the process model of Eq. 4.2 fitted per input to the encoder record and cross-validated, "
     "ωn = 1/Tw and ζ of the selected model (Figures 4.16–4.17); and, beyond the thesis, the link's residual "
     "mode identified from the gyroscope (docs/design.md §2)."),
    ("clearance", "Clearance model",
     "Thesis §4.2, end: the contact law of Eq. 4.3 added to the identified drive and calibrated until the "
     "simulated link rate matches the gyro record; agreement by Eq. 4.1 (Figures 4.19–4.20)."),
    ("simulated", "Simulated tests",
     "Thesis §5.1.1 and §5.2.1: every input, unshaped and shaped, on the model with clearance "
     "(Figures 5.1–5.7, 5.10–5.17), and the shapers' sensitivity to a frequency error."),
    ("rig", "Rig tests",
     "Thesis §5.1.2, §5.2.2 and Appendix B: repeated trials, Eq. 5.1 mean deviation without and with "
     "shaping, improvement (Tables 5.1, 5.2, B.1–B.6; Figures 5.8, 5.9, 5.18–5.20)."),
    ("ambiguities", "Ambiguities settled", "What the thesis leaves open, and how this study settled it."),
    ("differences", "Where we differ and why",
     "Every number the thesis also published, in one list, with the verdict, its criterion and the reason."),
]
SECTION_IDS = [s[0] for s in SECTIONS]
SECTION_TITLES = {s[0]: s[1] for s in SECTIONS}

# The page is rendered from python/templates (Debian's python3-jinja2): report.html.j2 is the page,
# parts.html.j2 its pieces (figures, facts, compared numbers, shapers, ambiguities), report.css and
# report.js are inlined. Autoescaping is on; what this module builds itself is passed as Markup.
TEMPLATE_DIR = Path(__file__).resolve().parent / "templates"
TEMPLATES = jinja2.Environment(loader=jinja2.FileSystemLoader(str(TEMPLATE_DIR)), autoescape=True,
                               undefined=jinja2.StrictUndefined, trim_blocks=True, lstrip_blocks=True,
                               keep_trailing_newline=True)


def parts():
    """The macros of parts.html.j2."""
    return TEMPLATES.get_template("parts.html.j2").module


# PNGs are drawn at 150 dpi; shown at 0.75 × their pixel size the 9.5 pt figure text is about the
# size of the page's body text.
DISPLAY_SCALE = 0.75


# ----------------------------------------------------------------------------------------------
# Formatting


def esc(v) -> str:
    return html.escape(str(v), quote=True)


_SUP = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def fmt(v, digits: int = 4) -> str:
    """A number for a table cell: 4 significant digits, ×10ⁿ below 10⁻³ or from 10⁵."""
    if v is None:
        return "—"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, str):
        return v
    v = float(v)
    if v == 0:
        return "0"
    if abs(v) < 1e-3 or abs(v) >= 1e5:
        mant, exp = f"{v:.{digits - 1}e}".split("e")
        if "." in mant:
            mant = mant.rstrip("0").rstrip(".")
        return minus(f"{mant}×10{str(int(exp)).translate(_SUP)}")
    s = f"{v:.{digits}g}"
    if "e" in s:
        s = f"{v:.0f}"
    return minus(s)


def column_format(values, extra_decimals: int = 0):
    """One number format for a column of one quantity (issue 22.11: 0.38 beside 0.3845 read as different
    precisions): fixed decimals giving the largest value 4 significant digits (plus `extra_decimals`), or
    ×10ⁿ for every value when the smallest would print as 0 in those decimals."""
    v = [abs(float(x)) for x in values if isinstance(x, (int, float)) and not isinstance(x, bool) and x]
    if not v:
        return fmt
    decimals = 3 - math.floor(math.log10(max(v))) + extra_decimals
    if max(v) >= 1e5 or decimals > 6 or round(min(v), max(decimals, 0)) == 0:
        return lambda x: fmt(x) if x is None or x == 0 else _sci(float(x))
    decimals = max(decimals, 0)
    return lambda x: "—" if x is None else minus(f"{float(x):.{decimals}f}")


def printed_format(printed: list, extra_decimals: int = 0):
    """The format of the thesis's printed digits ("0.270": 3 decimals; "1.56×10⁻⁴": ×10ⁿ), with
    `extra_decimals` more, for a number computed from them (the s.d. of its trials)."""
    texts = [str(x) for x in printed if x]
    if not texts or any("×" in x for x in texts):
        return lambda x: fmt(x) if x is None or x == 0 else _sci(float(x), 3)
    decimals = max(len(x.split(".")[1]) if "." in x else 0 for x in texts) + extra_decimals
    return lambda x: "—" if x is None else minus(f"{float(x):.{decimals}f}")


def _sci(v: float, digits: int = 4) -> str:
    mant, exp = f"{v:.{digits - 1}e}".split("e")
    return minus(f"{mant}×10{str(int(exp)).translate(_SUP)}")


def minus(s: str) -> str:
    """A number's sign as the typographic minus (U+2212), the same in every cell."""
    return s.replace("-", "−")


def fmt_signed(v) -> str:
    if v is None:
        return "—"
    if float(v) == 0:
        return "0"
    s = fmt(v)
    return s if s.startswith("−") else "+" + s


def fmt_pct(rel) -> str:
    return "—" if rel is None else minus(f"{100 * rel:+.1f} %")


def thesis_num(v, text: str | None = None) -> str:
    """A thesis number as the thesis printed it (results.json carries its digits: 0.270, 1.56×10⁻⁴)."""
    return minus(esc(text)) if text else fmt(v)  # the printed digits, with the page's one minus sign


WORSE_MARK = '<span class="worse-mark" title="worse than unshaped">▼ worse than unshaped</span>'


def interval_html(ci) -> str:
    """A 95 % bootstrap interval [lo, hi], marked "not significant" when it holds 0."""
    if not ci:
        return ""
    ns = ci[0] <= 0.0 <= ci[1]
    return (f' <span class="ci" title="95 % bootstrap interval over the trials">{minus(f"[{ci[0]:.1f}, {ci[1]:.1f}]")}</span>'
            + (' <span class="ns" title="the interval contains 0">not significant</span>' if ns else ""))


def improvement_html(v, ci=None) -> str:
    """Our improvement %: one decimal (as the thesis prints it), its interval, and the worse-than-unshaped
    mark when it is negative."""
    if v is None:
        return "—"
    return minus(f"{v:.1f} %") + (" " + WORSE_MARK if v < 0 else "") + interval_html(ci)


def worse_td(content: str, worse: bool, extra_class: str = "") -> str:
    cls = " ".join(x for x in (extra_class, "worse" if worse else "") if x)
    return f'<td{f" class={chr(34)}{cls}{chr(34)}" if cls else ""}>{content}</td>'


def unit_text(u) -> str:
    u = pretty_unit(u or "")
    return "" if u in ("", "–") else u


def with_unit(v, unit: str) -> str:
    s = fmt(v)
    return f"{s} {esc(unit)}" if unit and v is not None else s


def verdict_cell(agrees, colspan: int = 1, better: bool = False) -> str:
    """agrees / differs / not compared; a difference in clearshape's favour (a larger improvement, a
    smaller shaped mean deviation) is not drawn in the warning colour."""
    span = f' colspan="{colspan}"' if colspan > 1 else ""
    if agrees is None:
        return f'<td class="verdict na"{span}>not compared</td>'
    if agrees:
        return f'<td class="verdict ok"{span}>agrees</td>'
    if better:
        return f'<td class="verdict diff better"{span}>differs (ours better)</td>'
    return f'<td class="verdict diff"{span}>differs</td>'


def ours_better(c) -> bool:
    """Whether a difference is in clearshape's favour: a larger improvement, a smaller shaped mean."""
    if c is None or c.diff is None or c.agrees is not False:
        return False
    if c.kind == "improvement":
        return c.diff > 0
    return c.kind == "mean" and c.column is not None and not c.column.unshaped and c.diff < 0


def slug(s) -> str:
    return re.sub(r"[^a-z0-9]+", "-", str(s).lower()).strip("-") or "x"


def thesis_number_key(num) -> tuple:
    """Sort key of a thesis figure/table number: "4.16" → (4, 16), "B.3" → (100, 3); None last."""
    if num is None:
        return (999, 0)
    m = re.match(r"^\s*([0-9]+|[A-Za-z])\.([0-9]+)", str(num))
    if not m:
        return (998, 0)
    a = int(m.group(1)) if m.group(1).isdigit() else 100 + ord(m.group(1).upper()) - ord("A") - 1
    return (a, int(m.group(2)))


def png_size(data: bytes) -> tuple[int, int]:
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        return 0, 0
    return struct.unpack(">II", data[16:24])


# ----------------------------------------------------------------------------------------------
# Where each table and figure goes


def section_of_number(num) -> str | None:
    a, b = thesis_number_key(num)
    if a == 4:
        return "consistency" if b <= 8 else ("identification" if b <= 17 else "clearance")
    if a == 5:
        return "rig" if b in (8, 9) or b >= 18 else "simulated"
    if a == 101:  # Appendix B
        return "rig"
    return None


_PREFIX_SECTIONS = [("consistency", "consistency"), ("identification", "identification"),
                    ("link-mode", "identification"), ("drive", "identification"), ("clearance", "clearance"),
                    ("contact", "clearance"), ("simulation", "simulated"), ("shaper-sensitivity", "simulated"),
                    ("sensitivity", "simulated"), ("rig", "rig"), ("mean-deviation", "rig"), ("md-summary", "rig")]


def section_of_figure(spec: dict) -> str:
    sec = str(spec.get("section") or "").lower()
    if sec in SECTION_IDS:
        return sec
    if str(spec.get("kind", "")).lower() == "md-summary":
        return "rig"
    fid = str(spec.get("id", "")).lower()
    for prefix, s in _PREFIX_SECTIONS:
        if fid.startswith(prefix):
            return s
    return (section_of_number(spec.get("thesis_figure")) or section_of_number(spec.get("thesis_table"))
            or "simulated")


def section_of_table(t: tbl.Table) -> str:
    tid = t.id.lower()
    if "model" in tid or "cross-validation" in tid or tid.startswith("link-mode") or tid.startswith("identification"):
        return "identification"
    if "clearance" in tid or "contact" in tid:
        return "clearance"
    if "simulation" in tid:
        return "simulated"
    if (t.kind == "mean-deviation" and t.is_trials) or t.kind == "improvement":
        return "rig"
    if t.kind == "consistency":
        return "consistency"
    return section_of_number(t.id) or "rig"


# ----------------------------------------------------------------------------------------------
# Context and the reasons for differences


NOT_SCORED_CRITERION = "not scored: this rig is not the thesis's, so its number is shown for scale only"


class Context:
    def __init__(self, results: dict):
        self.results = results
        self.study = results.get("study", {}) if isinstance(results.get("study"), dict) else {}
        self.mode = str(self.study.get("mode", "")).lower()
        rig = self.study.get("rig", "")
        self.rig_text = json.dumps(rig) if isinstance(rig, (dict, list)) else str(rig)
        self.simulated_rig = (not self.rig_text) or bool(re.search(r"\bsim|synthetic|fixture", self.rig_text, re.I))
        rig_kind = results.get("rig", {}).get("kind") if isinstance(results.get("rig"), dict) else None
        if isinstance(rig_kind, str):  # results.json "rig": {kind, description} decides when present
            self.simulated_rig = rig_kind.startswith("simulated")
        self.rig_kind = rig_kind if isinstance(rig_kind, str) else ("simulated-thesis" if self.simulated_rig
                                                                   else "physical")
        rig = results.get("rig") if isinstance(results.get("rig"), dict) else {}
        self.rig_description = str(rig.get("description") or self.rig_text)
        # What the rig is comes from results.json "rig" (study/report.cpp rig_document): its summary,
        # whether its truth was calibrated to the thesis's unshaped measurements (only the built-in
        # thesis rig) and whether its numbers are scored against the thesis's (that rig, or a physical
        # or recorded rig repeating the experiment; a what-if rig shows them for scale only). Results
        # written before those keys existed are read as the thesis rig when simulated-thesis.
        thesis_rig = self.rig_kind == "simulated-thesis"
        self.calibrated = bool(rig.get("calibrated_to_thesis", thesis_rig))
        self.scored = bool(rig.get("scored_against_thesis", thesis_rig or not self.simulated_rig))
        self.rig_summary = str(rig.get("summary") or "")
        self.documented = rig.get("documented") if isinstance(rig.get("documented"), dict) else {}
        self.synthetic = bool(results.get("synthetic")) or "fixture" in self.rig_text.lower()
        self.sections = results.get("sections", {}) if isinstance(results.get("sections"), dict) else {}


def why(ctx: Context, t: tbl.Table, c: tbl.Comparison) -> str:
    """Why our number differs from the thesis's (shown only when it does, or is not compared)."""
    if c.agrees or c.agrees is None:
        return ""
    if ctx.synthetic:
        return "Synthetic fixture: the numbers are made up to exercise the report; they are not results."
    col = c.column
    own = f" {col.note}" if col is not None and col.note else ""
    sec = section_of_table(t)
    direction = "lower" if (c.diff or 0) < 0 else "higher"
    if sec == "consistency":
        if ctx.simulated_rig:
            return (f"Ours is {direction}. The simulated rig repeats its motor motion exactly apart from what it "
                    "randomizes (sensor noise, the link's initial position in the play), so Eq. 4.1 measures that "
                    "and the encoder quantization; the thesis's errors also hold the real drive's run-to-run "
                    "variation." + own)
        return f"Ours is {direction}: the run-to-run variation of a different drive and DAQ." + own
    if c.kind == "parameter" and sec == "identification":
        sd = ""
        if col is not None and col.ours_std:
            i = next((k for k, r in enumerate(t.row_labels) if r == c.quantity), None)
            if i is not None and i < len(col.ours_std) and col.ours_std[i] is not None:
                sd = f" Our fit's standard error is ±{fmt(col.ours_std[i], 2)}."
        return ("Identified from this rig's records by clearshape's process-model fit, not by MATLAB's toolbox "
                "on the thesis's rig. The position-mode model with ζ ≈ 1 and millisecond Tz and Tp3 is weakly "
                "identifiable: the zero and the third pole nearly cancel, so those two trade off against each "
                "other while the response barely changes." + sd if ctx.mode == "position" else
                "Identified from this rig's records by clearshape's process-model fit through the §3.3 filter "
                "chain, not by MATLAB's toolbox on the thesis's rig." + sd) + own
    if sec == "clearance" and "agreement" not in c.quantity.lower():
        return ("Set or calibrated by the study's clearance stage for this rig, not taken from the thesis (which "
                "chose n = 1.5 after earlier studies, §4.2); the contact law is judged by the agreement it "
                "produces." + own)
    if sec == "clearance":
        status = ctx.sections.get("clearance", {}).get("status") if isinstance(ctx.sections.get("clearance"), dict) else None
        extra = f" The contact fit reported: {status}." if status else ""
        return ("Eq. 4.1 between the calibrated clearance model and the rig's gyro record; ours is "
                f"{direction}, i.e. the contact model follows the rig's link rate "
                f"{'less' if direction == 'higher' else 'more'} closely than the thesis's Simulink model followed "
                "its gyroscope." + extra + own)
    if c.kind == "improvement":
        return ("Follows from the two mean deviations it divides: the unshaped one is a calibration target, the "
                "shaped one a prediction; see their own lines." + own)
    if col is not None and col.unshaped:
        if ctx.calibrated and ctx.mode == "position":
            return ("Calibration target: the simulated rig's play, flank stiffness and damping and gyro noise are "
                    "fitted once (clearshape calibrate-rig) so that its unshaped trials reproduce the unshaped ('without IS') "
                    f"means of Tables B.1–B.5 together; ours is {direction} by the calibration residual for this "
                    "input (one physical rig cannot match every input exactly), or the calibration in use is not "
                    "current." + own)
        if ctx.simulated_rig:
            return ("Not a calibration target in speed mode: the unshaped level depends on the step amplitude, "
                    "which the thesis does not give (the protocol's choice)." + own)
        return "Measured on a different rig: the unshaped level depends on its play, link inertia and friction." + own
    if ctx.simulated_rig:
        return (f"Prediction (nothing was tuned to it); ours is {direction}. A shaped result depends on how closely "
                "the identified mode matches the simulated link's ringing, and on what the simulated rig leaves out "
                "of the real one (unmodelled friction and link flexibility, the real gyro's noise and drift)." + own)
    return "Measured on a different rig, with shapers designed from its own identified mode." + own


def improvement_spreads(tables: list[tbl.Table]) -> dict:
    """Our improvement % (rounded) → the bootstrap interval of ours − thesis from the trial tables, so
    that a table that repeats an improvement (B.6) judges it with the same criterion as its trial table."""
    out = {}
    for t in tables:
        if not t.is_trials:
            continue
        for c in t.columns:
            if c.improvement is not None and c.difference_ci:
                out[round(c.improvement, 9)] = c.difference_ci
    return out


def comparisons_of(ctx: Context, t: tbl.Table, spreads: dict | None = None) -> list[tbl.Comparison]:
    out = tbl.compare_table(t)
    if t.kind == "improvement" and spreads:
        for c in out:
            ci = spreads.get(round(c.ours, 9)) if c.ours is not None else None
            if ci:
                v = tbl.interval_verdict(c.ours, c.thesis, ci)
                c.diff, c.rel, c.agrees, c.criterion = v["diff"], v["rel"], v["agrees"], v["criterion"]
    # Contact parameters whose units the thesis does not state cannot be compared (docs/design.md §2).
    _, thesis_col = tbl.parameter_pair(t) if t.kind == "parameters" else (None, None)
    if thesis_col is not None and "unstated" in thesis_col.label.lower():
        for c in out:
            if re.search(r"N·m|N\.m|Nm", c.quantity):
                c.agrees, c.criterion = None, "the thesis states no unit for it: not comparable"
    # A contact parameter the fit did not identify (fixed, at a bound, or with a standard error above the
    # criterion) is not a finding: it is not scored against the thesis's either.
    if section_of_table(t) == "clearance":
        params = {str(p.get("name")): p for p in (ctx.sections.get("clearance") or {}).get("parameters") or []
                  if isinstance(p, dict)}
        for c in out:
            p = params.get(str(c.quantity).split(" ")[0])
            if p is None or c.agrees is None:
                continue
            if not p.get("free", True):
                c.agrees, c.criterion = None, "fixed by the protocol, not fitted: not comparable"
            elif p.get("at_bound") or not p.get("identifiable", True):
                c.agrees, c.criterion = None, ("not identifiable from this record (at a bound of its range or its "
                                               "standard error too large): not comparable")
    if not ctx.scored:
        for c in out:
            if c.thesis is not None:
                c.agrees, c.criterion = None, NOT_SCORED_CRITERION
    for c in out:
        c.why = why(ctx, t, c)
    return out


# ----------------------------------------------------------------------------------------------
# Tables


def is_thesis_table(tid: str) -> bool:
    """A table the thesis prints ("4.2", "5.1", "B.3"); clearshape's own tables ("4.3-clearance",
    "4.2-model", "5.2-simulation", "reach") are not named like them."""
    return re.fullmatch(r"(?:[0-9]+|B)\.[0-9]+", str(tid)) is not None


def _caption(t: tbl.Table, extra: str = "") -> str:
    head = (f"Table {esc(t.id)} — {esc(t.title)}" if is_thesis_table(t.id)
            else f"{esc(t.title)} <span class=\"tid\">(clearshape table {esc(t.id)})</span>")
    unit = unit_text(t.unit)
    sub = "; ".join(x for x in ((f"unit: {esc(unit)}" if unit else ""), extra) if x)
    return f"<caption>{head}<span class=\"unit\">{sub}</span></caption>"


def recomputed_cell(printed, recomputed, printed_text: str | None = None, unit: str = "") -> str:
    """A thesis number recomputed from the thesis's own numbers, beside (never under) its printed one:
    shown when it was not printed, or differs from the printed one beyond the printed digits."""
    if recomputed is None:
        return '<td colspan="2"></td>'
    shown = printed_text if printed_text and "×" not in printed_text else (repr(float(printed)) if printed is not None
                                                                          else "")
    digits = len(shown.split(".")[1]) if "." in shown and "e" not in shown else 4
    if printed is not None and abs(recomputed - printed) <= 0.5 * 10 ** -digits * (1 + 1e-9):  # rounds to it
        return '<td colspan="2"></td>'
    what = "not printed" if printed is None else f"printed {thesis_num(printed, printed_text)}{unit}"
    return (f'<td colspan="2" class="recomputed">{fmt(round(recomputed, digits + 1))}{unit} '
            f'<span class="sub">recomputed ({what})</span></td>')


def render_trial_table(t: tbl.Table, comps: list[tbl.Comparison]) -> str:
    """Repeated trials: per column ours beside the thesis's trials; mean, s.d., Δ of the means,
    improvement and verdicts in the footer. Trials are exchangeable (trial i here has nothing to do
    with trial i in the thesis), so differences are given for the means, not trial by trial."""
    n = max([len(t.row_labels)] + [len(c.thesis) for c in t.columns])
    cols = t.columns
    out = [f'<table class="results trials" id="table-{slug(t.id)}">',
           _caption(t, "Δ = clearshape − thesis, on the means; trials are exchangeable, so they are listed side "
                       "by side without a per-trial difference"),
           '<thead><tr><th rowspan="2" scope="col">trial</th>']
    for c in cols:
        out.append(f'<th colspan="2" scope="colgroup" class="grp">{esc(c.label)}</th>')
    out.append("</tr><tr>")
    for _ in cols:
        out.append('<th scope="col">clearshape</th><th scope="col" class="thesis">thesis</th>')
    out.append("</tr></thead><tbody>")
    ours_fmt = {id(c): column_format(list(c.ours) + [c.ours_mean]) for c in cols}
    for i in range(n):
        out.append(f'<tr><th scope="row">{i + 1}</th>')
        for c in cols:
            o = c.ours[i] if i < len(c.ours) else None
            th = c.thesis[i] if i < len(c.thesis) else None
            out.append(f"<td>{ours_fmt[id(c)](o) if i < len(c.ours) else ''}</td><td class=\"thesis\">"
                       f"{thesis_num(th, c.thesis_text(i)) if i < len(c.thesis) else ''}</td>")
        out.append("</tr>")
    out.append("</tbody><tfoot>")
    by = {(id(c.column), c.kind): c for c in comps}

    def line(label, cls, cells):
        return f'<tr class="{cls}"><th scope="row">{label}</th>{"".join(cells)}</tr>'

    means, sds, deltas, verdicts, recomputed_means = [], [], [], [], []
    for c in cols:
        m = by.get((id(c), "mean"))
        om = m.ours if m else (c.ours_mean if c.ours_mean is not None else tbl.mean_sd(c.ours)[0])
        tm = c.thesis_mean
        means.append(f"<td>{ours_fmt[id(c)](om)}</td><td class=\"thesis\">{thesis_num(tm, c.thesis_mean_printed)}</td>")
        recomputed_means.append(recomputed_cell(tm, tbl.mean_sd(c.thesis)[0], c.thesis_mean_printed))
        osd = c.ours_sd if c.ours_sd is not None else tbl.mean_sd(c.ours)[1]
        # s.d. in its column's decimals (the thesis's printed ones), one more digit
        tsd = tbl.mean_sd(c.thesis)[1]
        sds.append(f"<td>{column_format(list(c.ours) + [om], 1)(osd)}</td><td class=\"thesis\">"
                   f"{printed_format(c.thesis_printed, 1)(tsd)}</td>")
        deltas.append(f'<td colspan="2" class="delta">{fmt_signed(m.diff) if m else "—"}'
                      f'{(" (" + fmt_pct(m.rel) + ")") if m and m.rel is not None else ""}</td>')
        verdicts.append(verdict_cell(m.agrees if m else None, 2, ours_better(m)))
    out.append(line("mean", "mean", means))
    if any("recomputed" in x for x in recomputed_means):
        out.append(line("mean of the thesis's trials, recomputed", "recomputed", recomputed_means))
    out.append(line("s.d.", "sd", sds))
    out.append(line("Δ of the means", "delta", deltas))
    out.append(line("mean vs thesis", "verdicts", verdicts))
    if any(c.improvement is not None or c.thesis_improvement is not None for c in cols):
        imps, ivs, recomputed = [], [], []
        for c in cols:
            m = by.get((id(c), "improvement"))
            if m is None:
                imps.append('<td colspan="2"></td>')
                ivs.append('<td colspan="2"></td>')
                recomputed.append('<td colspan="2"></td>')
                continue
            thesis = (thesis_num(m.thesis, c.thesis_improvement_printed) + " %") if m.thesis is not None else "—"
            imps.append(worse_td(improvement_html(m.ours, c.improvement_ci), m.ours is not None and m.ours < 0)
                        + f'<td class="thesis">{thesis}</td>')
            ivs.append(verdict_cell(m.agrees, 2, ours_better(m)))
            recomputed.append(recomputed_cell(c.thesis_improvement, c.thesis_improvement_recomputed,
                                              c.thesis_improvement_printed, " %"))
        out.append(line("improvement", "improvement", imps))
        if any("recomputed" in x for x in recomputed):
            out.append(line("thesis's improvement recomputed from its means", "recomputed", recomputed))
        out.append(line("improvement vs thesis", "verdicts", ivs))
    out.append("</tfoot></table>")
    return "".join(out)


def render_parameter_table(t: tbl.Table, comps: list[tbl.Comparison]) -> str:
    ours_col, thesis_col = tbl.parameter_pair(t)
    comp_by_row = {c.quantity: c for c in comps}
    cols = t.columns
    has_cmp = bool(comps)
    out = [f'<table class="results params" id="table-{slug(t.id)}">',
           _caption(t, (f"Δ = {esc(ours_col.label)} − {esc(thesis_col.label)}" if has_cmp and ours_col and thesis_col
                        else "")),
           '<thead><tr><th scope="col"></th>']
    for c in cols:
        cls = ' class="thesis"' if c.thesis and not c.ours else ""
        out.append(f"<th scope=\"col\"{cls}>{esc(c.label)}</th>")
        for k in c.extra:
            if k != "ours_std":
                out.append(f'<th scope="col">{esc(c.label)}: {esc(k.replace("_", " "))}</th>')
    if has_cmp:
        out.append('<th scope="col">Δ</th><th scope="col">Δ %</th><th scope="col">verdict</th>')
    out.append("</tr></thead><tbody>")
    for i, row in enumerate(t.row_labels):
        out.append(f'<tr><th scope="row">{esc(row)}</th>')
        for c in cols:
            vals = c.ours if c.ours else c.thesis
            v = vals[i] if i < len(vals) else None
            sd = c.ours_std[i] if c.ours_std and i < len(c.ours_std) else None
            cls = ' class="thesis"' if c.thesis and not c.ours else ""
            out.append(f"<td{cls}>{fmt(v)}{(' <span class=pm>± ' + fmt(sd, 2) + '</span>') if sd is not None else ''}</td>")
            for k, arr in c.extra.items():
                if k != "ours_std":
                    out.append(f"<td>{fmt(arr[i]) if i < len(arr) else ''}</td>")
        if has_cmp:
            m = comp_by_row.get(row)
            if m is None:
                out.append('<td></td><td></td><td></td>')
            else:
                out.append(f'<td class="delta">{fmt_signed(m.diff)}</td><td class="delta">{fmt_pct(m.rel)}</td>'
                           f"{verdict_cell(m.agrees)}")
        out.append("</tr>")
    out.append("</tbody></table>")
    return "".join(out)


def render_rowwise_table(t: tbl.Table, comps: list[tbl.Comparison]) -> str:
    """Rows that are not trials (e.g. B.6, per-input simulation results, matrices)."""
    cols = t.columns
    comp = {(id(c.column), c.quantity): c for c in comps}
    out = [f'<table class="results rows" id="table-{slug(t.id)}">',
           _caption(t, "Δ = clearshape − thesis" if comps else ""), '<thead><tr><th scope="col"></th>']
    for c in cols:
        if c.ours:
            out.append(f'<th scope="col">{esc(c.label)}</th>')
        for k in c.extra:
            out.append(f'<th scope="col">{esc(c.label)}: {esc(k.replace("_", " "))}</th>')
        if c.thesis:
            out.append('<th scope="col" class="thesis">thesis</th><th scope="col">Δ</th><th scope="col">verdict</th>')
    out.append("</tr></thead><tbody>")
    base = next((c for c in cols if c.unshaped and c.ours), None)
    for i, row in enumerate(t.row_labels):
        out.append(f'<tr><th scope="row">{esc(row)}</th>')
        for c in cols:
            if c.ours:
                v = c.ours[i] if i < len(c.ours) else None
                if t.kind == "improvement":
                    ci = c.improvement_ci[i] if isinstance(c.improvement_ci, list) and i < len(c.improvement_ci) \
                        and isinstance(c.improvement_ci[i], list) else None
                    out.append(worse_td(improvement_html(v, ci), v is not None and v < 0))
                else:
                    worse = worse_than_unshaped(t, base, c, i)
                    out.append(worse_td(fmt(v) + ((" " + WORSE_MARK) if worse else ""), worse))
            for arr in c.extra.values():
                out.append(f"<td>{fmt(arr[i]) if i < len(arr) else '—'}</td>")
            if c.thesis:
                q = f"{row}" + (f" — {c.label}" if len(cols) > 1 else "")
                m = comp.get((id(c), q)) or comp.get((id(c), f"{row} — {c.label}")) or comp.get((id(c), str(row)))
                th = thesis_num(c.thesis[i], c.thesis_text(i)) if i < len(c.thesis) else "—"
                out.append(f"<td class=\"thesis\">{th}</td>"
                           f"<td class=\"delta\">{fmt_signed(m.diff) if m else '—'}</td>"
                           f"{verdict_cell(m.agrees if m else None, 1, ours_better(m))}")
        out.append("</tr>")
    out.append("</tbody></table>")
    return "".join(out)


def worse_than_unshaped(t: tbl.Table, base: tbl.Column | None, c: tbl.Column, i: int) -> bool:
    """A shaped mean deviation above the unshaped one of its row (a results table with a "none" column)."""
    if base is None or c is base or t.kind != "mean-deviation" or t.is_trials:
        return False
    v = c.ours[i] if i < len(c.ours) else None
    b = base.ours[i] if i < len(base.ours) else None
    return v is not None and b is not None and v > b


def transposed(t: tbl.Table) -> bool:
    """A results table (no thesis values) with more columns than rows reads better turned: one row per
    column (shaper), one column per row (input), so it fits the page instead of running off it."""
    return (not t.is_trials and t.kind != "parameters" and not any(c.thesis for c in t.columns)
            and len(t.columns) > len(t.row_labels) and 0 < len(t.row_labels) <= MAX_CELLS_PER_PART)


def render_transposed_table(t: tbl.Table) -> str:
    """One row per column of results.json, one column per row label; a column's other per-row
    values (e.g. delay_s) are shown under the value."""
    out = [f'<table class="results rows turned" id="table-{slug(t.id)}">',
           _caption(t, "one row per quantity, one column per input" if t.kind == "reach"  # the measurement floor
                    else "one row per shaper, one column per input"), '<thead><tr><th scope="col"></th>']
    out += [f'<th scope="col">{esc(r)}</th>' for r in t.row_labels]
    out.append("</tr></thead><tbody>")
    base = next((c for c in t.columns if c.unshaped and c.ours), None)
    for c in t.columns:
        out.append(f'<tr><th scope="row">{esc(c.label)}</th>')
        for i in range(len(t.row_labels)):
            v = c.ours[i] if i < len(c.ours) else None
            extra = "".join(f'<span class="sub">{esc(k.removesuffix("_s").replace("_", " "))} {fmt(arr[i])}'
                            f'{" s" if k.endswith("_s") else ""}</span>'
                            for k, arr in c.extra.items() if i < len(arr) and arr[i] is not None)
            worse = worse_than_unshaped(t, base, c, i)
            out.append(worse_td(f"{fmt(v)}{(' ' + WORSE_MARK) if worse else ''}{extra}", worse))
        out.append("</tr>")
    out.append("</tbody></table>")
    return "".join(out)


def is_composite(t: tbl.Table, ids: set) -> bool:
    """A table made of other tables' columns (keys "<table id>:<column>", e.g. 5.2 = B.1 + B.5)."""
    refs = [c.key.split(":", 1)[0] for c in t.columns if ":" in c.key]
    return bool(refs) and len(refs) == len(t.columns) and all(r in ids and r != t.id for r in refs)


# Widest table part, in value cells beside the row labels: at a 1400 px window (and in print) the
# page's 64rem column holds about this many numeric cells next to an input's name.
MAX_CELLS_PER_PART = 8


def _empty(col: tbl.Column) -> bool:
    vals = list(col.ours) + list(col.thesis) + [v for arr in col.extra.values() for v in arr]
    return all(v is None for v in vals) and col.improvement is None and col.thesis_improvement is None \
        and col.ours_mean is None and col.thesis_mean is None


def without_empty_columns(t: tbl.Table) -> tuple[tbl.Table, list[tbl.Column]]:
    """The table without its columns that hold no value at all (e.g. shapers that could not be
    designed), and those columns, so the page can say which were left out and why."""
    empty = [c for c in t.columns if _empty(c)]
    if not empty or len(empty) == len(t.columns):
        return t, []
    return dataclasses.replace(t, columns=[c for c in t.columns if not _empty(c)]), empty


def _cells(t: tbl.Table, c: tbl.Column) -> int:
    if t.is_trials:
        return 2
    return (1 if c.ours else 0) + len(c.extra) + (3 if c.thesis else 0)


def table_parts(t: tbl.Table) -> list[tbl.Table]:
    """The table split by columns into parts of at most MAX_CELLS_PER_PART value cells, so no part is
    wider than the page; the unshaped column, when there is one, heads every part."""
    if t.kind == "parameters":
        return [t]
    base = next((c for c in t.columns if c.unshaped), None)
    rest = [c for c in t.columns if c is not base]
    budget = MAX_CELLS_PER_PART - (_cells(t, base) if base is not None else 0)
    parts, cur, used = [], [], 0
    for c in rest:
        n = _cells(t, c)
        if cur and used + n > budget:
            parts.append(cur)
            cur, used = [], 0
        cur.append(c)
        used += n
    if cur or not parts:
        parts.append(cur)
    if len(parts) == 1:
        return [t]
    lead = [base] if base is not None else []
    return [dataclasses.replace(t, columns=lead + p) for p in parts]


def render_table(t: tbl.Table, comps: list[tbl.Comparison], composite: bool = False) -> str:
    if composite:
        refs = sorted({c.key.split(":", 1)[0] for c in t.columns})
        inner = render_table(t, comps)
        return (f'<details class="composite"><summary>Table {esc(t.id)} — {esc(t.title)}: the same trials as '
                f'Table(s) {esc(", ".join(refs))} (the thesis prints them twice); show</summary>{inner}</details>')
    t, empty = without_empty_columns(t)
    parts = [t] if transposed(t) else table_parts(t)
    bodies = []
    for k, part in enumerate(parts):
        if transposed(part):
            body = render_transposed_table(part)
        elif t.is_trials:
            body = render_trial_table(part, comps)
        elif t.kind == "parameters":
            body = render_parameter_table(part, comps)
        else:
            body = render_rowwise_table(part, comps)
        if len(parts) > 1:  # ids stay unique, the caption says which part
            body = body.replace(f'id="table-{slug(t.id)}"', f'id="table-{slug(t.id)}-part{k + 1}"', 1)
            body = body.replace("</caption>", f'<span class="part">part {k + 1} of {len(parts)}</span></caption>', 1)
        bodies.append(f'<div class="table-wrap">{body}</div>')
    notes = []
    if empty:
        reasons = sorted({c.note for c in empty if c.note})
        notes.append(f'<p class="note empty-columns"><strong>Left out, no values:</strong> '
                     f'{esc(", ".join(c.label for c in empty))}'
                     + (f" — {esc(' '.join(reasons))}" if reasons else "") + "</p>")
    if t.note:
        notes.append(f'<p class="note">{esc(t.note)}</p>')
    return "".join(bodies) + "".join(notes)


# ----------------------------------------------------------------------------------------------
# Figures


def render_figure(rec: dict, number: int) -> str:
    spec = rec["spec"]
    num = spec.get("thesis_figure")
    f = {"label": f"Figure {number}" + (f" (analogue of thesis Fig. {num})" if num else " (clearshape)"),
         "title": tbl.plain_label(str(spec.get("title") or rec["id"])), "anchor": f"fig-{slug(rec['id'])}",
         "caption": tbl.plain_label(". ".join(x for x in (str(spec.get("caption") or ""), rec.get("caption") or "") if x)),
         "error": None, "pdf": None, "png": None}
    if rec.get("error") or not rec.get("png"):
        f["error"] = rec.get("error") or "no PNG"
        return str(parts().figure(f))
    data = Path(rec["png"]).read_bytes()
    w, h = png_size(data)
    f.update(png_b64=base64.b64encode(data).decode("ascii"), width=round(w * DISPLAY_SCALE),
             height=round(h * DISPLAY_SCALE), png=Path(rec["png"]).name,
             pdf=Path(rec["pdf"]).name if rec.get("pdf") else None)
    return str(parts().figure(f))


def md_summary_spec(results: dict) -> dict | None:
    """The report's own summary figure: Eq. 5.1 means without/with shaping and improvements of every
    rig trial table, beside the thesis's (one bar group per table and published shaper column)."""
    rows, seen = [], set()
    unit = ""
    for raw in results.get("tables", []) or []:
        t = tbl.normalise(raw)
        if not (t.is_trials and t.kind == "mean-deviation") or section_of_table(t) != "rig":
            continue
        base = next((c for c in t.columns if c.unshaped), None)
        if base is None:
            continue
        for c in t.columns:
            if c is base or c.thesis_mean is None:
                continue
            key = (tuple(base.ours), tuple(c.ours))
            if key in seen:
                continue
            seen.add(key)
            shaped = [x for x in t.columns if not x.unshaped and x.thesis_mean is not None]
            label = f"{t.id} {c.role.upper()}" if len(shaped) > 1 else t.id
            rows.append({"table": t.id, "label": label, "role": c.role,
                         "ours_without": base.ours_mean, "thesis_without": base.thesis_mean,
                         "ours_with": c.ours_mean, "thesis_with": c.thesis_mean, "ours_improvement": c.improvement,
                         "ours_improvement_ci95": c.improvement_ci, "thesis_improvement": c.thesis_improvement})
            unit = t.unit
    if not rows:
        return None
    return {"id": "md-summary", "kind": "md-summary", "thesis_figure": None, "section": "rig", "unit": unit,
            "title": "Eq. 5.1 mean deviation without and with shaping, and the improvement, clearshape beside "
                     "the thesis (means over the trials)", "rows": rows}


# ----------------------------------------------------------------------------------------------
# Generic rendering of anything else


def render_generic(value) -> str:
    if isinstance(value, dict):
        if not value:
            return "—"
        return '<dl class="kv">' + "".join(f"<dt>{esc(k.replace('_', ' '))}</dt><dd>{render_generic(v)}</dd>"
                                           for k, v in value.items()) + "</dl>"
    if isinstance(value, list):
        if value and all(isinstance(v, dict) for v in value):
            keys = []
            for v in value:
                keys += [k for k in v if k not in keys]
            head = "".join(f'<th scope="col">{esc(k.replace("_", " "))}</th>' for k in keys)
            body = "".join("<tr>" + "".join(f"<td>{render_generic(v.get(k))}</td>" for k in keys) + "</tr>"
                           for v in value)
            return (f'<div class="table-wrap"><table class="generic"><thead><tr>{head}</tr></thead>'
                    f"<tbody>{body}</tbody></table></div>")
        if all(not isinstance(v, (dict, list)) for v in value):
            return ", ".join(esc(fmt(v)) if isinstance(v, (int, float)) and not isinstance(v, bool) else esc(v)
                             for v in value) or "—"
        return "<ul>" + "".join(f"<li>{render_generic(v)}</li>" for v in value) + "</ul>"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, (int, float)):
        return esc(fmt(value))
    return "—" if value is None else esc(value)


# ----------------------------------------------------------------------------------------------
# Sections


def section(sid: str, content: str, empty: str = "") -> dict:
    """One section of the page for report.html.j2: number, title, intro and its content (markup)."""
    n = SECTION_IDS.index(sid) + 1
    return {"id": sid, "number": n, "title": SECTIONS[n - 1][1], "intro": SECTIONS[n - 1][2],
            "content": Markup(content), "empty": empty}


def setup_html(ctx: Context, study_dir: Path, records: list[dict]) -> str:
    st, r = ctx.study, ctx.results
    items = [("study", st.get("name")), ("title", st.get("title")), ("operation mode", st.get("mode")),
             ("rig", st.get("rig")), ("random seed", st.get("seed")),
             ("quick variant (fewer repetitions, shorter records)", st.get("quick")),
             ("protocol hash", st.get("protocol_hash")), ("clearshape", r.get("clearshape_version")),
             ("results schema", r.get("results_schema_version", r.get("schema_version")))]
    proto = r.get("protocol") if isinstance(r.get("protocol"), dict) else {}
    for key, lab in (("repetitions", "repetitions per input"), ("record_s", "record length (s)"),
                     ("sample_rate_hz", "sample rate (Hz)"), ("source", "protocol file")):
        if key in proto:
            items.append((lab, proto[key]))
    out = [facts_html(items)]
    if ctx.synthetic:
        out.append('<p class="warn" role="note"><strong>Synthetic fixture.</strong> These numbers are made up by '
                   "python/clearshape_plot/fixture.py to exercise the report; they are not results.</p>")
    # What the rig is, also for the fixture (its results.json says which kind it stands for).
    out.append(f'<p class="note" id="rig-kind" data-rig-kind="{esc(ctx.rig_kind)}">{rig_note(ctx)}</p>')
    if st.get("quick"):
        out.append('<p class="warn" role="note"><strong>Quick variant.</strong> Fewer repetitions and shorter '
                   "records than the thesis's programme, for tests; the thesis always lists its 10 trials.</p>")
    inputs = proto.get("inputs")
    if isinstance(inputs, list) and inputs:
        rows_in = []
        for i in inputs:
            if not isinstance(i, dict):
                continue
            params = ", ".join(f"{k.replace('_', ' ')} = {render_generic(v)}" for k, v in i.items()
                               if k not in ("name", "label", "type") and v is not None)
            rows_in.append(f"<tr><th scope=\"row\">{esc(i.get('label', i.get('name', '')))}</th>"
                           f"<td>{esc(i.get('name', ''))}</td><td>{esc(i.get('type', ''))}</td><td>{params}</td></tr>")
        out.append('<h3>Inputs</h3><div class="table-wrap"><table class="generic"><thead><tr><th scope="col">input'
                   '</th><th scope="col">name</th><th scope="col">type</th><th scope="col">parameters (units in the '
                   'names)</th></tr></thead><tbody>' + "".join(rows_in) + "</tbody></table></div>")
    units = r.get("units")
    if isinstance(units, dict):
        out.append("<h3>Units</h3>" + render_generic(units))
    if proto:
        out.append("<details><summary>Effective protocol (as run)</summary><pre>"
                   + esc(json.dumps(proto, indent=2, ensure_ascii=False)) + "</pre></details>")
    drawn = sum(1 for x in records if not x.get("error"))
    files = [f'<li><a href="{n}">{n}</a></li>' for n in ("results.json", "tables.md", "figures.json", "timing.json")
             if (study_dir / n).exists()]
    for d, what in (("data", "the data behind every figure (CSV)"), ("runs", "every run as CSV with a JSON sidecar")):
        if (study_dir / d).is_dir():
            files.append(f'<li><a href="{d}/">{d}/</a> — {what}</li>')
    out.append(f"<p>{drawn} of {len(records)} figures drawn (PNG and PDF in <a href=\"figures/\">figures/</a>). "
               f"Files of this study:</p><ul>{''.join(files)}</ul>")
    return "".join(out)


def facts_html(items) -> str:
    """(label, value) pairs as a definition list (parts.html.j2 facts); None values are left out."""
    return str(parts().facts([(k, Markup(render_generic(v))) for k, v in items if v is not None]))


def rig_note(ctx: Context) -> str:
    """What the rig is and what its numbers mean beside the thesis's, from results.json "rig"."""
    desc = f" ({esc(ctx.rig_description)})" if ctx.rig_description else ""
    what = esc(ctx.rig_summary.rstrip(". ")) if ctx.rig_summary else f"a rig of kind {esc(ctx.rig_kind)}"
    text = f"The rig is {what}{desc}."
    if ctx.calibrated:
        text += (" Because it was calibrated to what the thesis measured <em>without</em> shaping (docs/design.md "
                 "§2), its unshaped means are calibration targets — agreement there is by construction, not a "
                 "finding; the study never reads the rig's truth, and every shaped result is a prediction.")
    elif ctx.scored:
        text += " Every run is a measurement, not a calibrated prediction."
    else:
        text += (" Its numbers are <strong>not scored</strong> against the thesis's; the study never reads the "
                 "rig's truth, and every shaped result is a prediction.")
    return text


def identification_facts(ctx: Context) -> str:
    ident = ctx.sections.get("identification")
    lm = ctx.sections.get("link_mode")
    out = []
    if isinstance(ident, dict):
        dm = ident.get("drive_mode") if isinstance(ident.get("drive_mode"), dict) else {}
        facts = [("selected model (identified from input)", ident.get("selected_input")),
                 ("drive model ωn = 1/Tw (rad/s)", dm.get("natural_frequency_rad_s")),
                 ("drive model ζ", dm.get("damping_ratio"))]
        out.append(facts_html(facts))
    if isinstance(lm, dict) and lm.get("available", True):
        facts = [("link residual mode, from the gyro's free response after", lm.get("input")),
                 ("natural frequency (Hz)", lm.get("natural_frequency_hz")),
                 ("damping ratio", lm.get("damping_ratio")), ("note", lm.get("note"))]
        out.append(facts_html(facts))
    return "".join(out)


def clearance_facts(ctx: Context) -> str:
    cl = ctx.sections.get("clearance")
    if not isinstance(cl, dict):
        return ""
    return "<details><summary>Clearance fit, all numbers</summary>" + render_generic(cl) + "</details>"


def _table_by_id(results: dict, tid: str) -> dict | None:
    return next((t for t in results.get("tables") or [] if isinstance(t, dict) and t.get("id") == tid), None)


def _thesis_contact(results: dict) -> dict:
    """The thesis's contact law (K, D, n) from the clearance table's thesis column."""
    t = _table_by_id(results, "4.3-clearance")
    if not t:
        return {}
    col = next((c for c in t.get("columns") or [] if c.get("key") == "thesis"), None)
    if not col or not col.get("thesis"):
        return {}
    out = {}
    for label, v in zip(t.get("row_labels") or [], col["thesis"]):
        key = {"K": "K", "D": "D", "exponent": "n"}.get(str(label).split(" ")[0])
        if key and isinstance(v, (int, float)):
            out[key] = float(v)
    return out


def _rig_md(results: dict) -> tuple[float | None, float | None, str]:
    """Mean unshaped and shaped (ZVDD, link mode if present) Eq. 5.1 of the first rig table."""
    for tid in ("B.1", "5.1"):
        t = _table_by_id(results, tid)
        if not t:
            continue
        cols = {c.get("key"): c for c in t.get("columns") or []}
        shaped = cols.get("zvdd@link-mode") or cols.get("zvdd@drive-model")
        return ((cols.get("none") or {}).get("ours_mean"), (shaped or {}).get("ours_mean"), tid)
    return None, None, ""


def clearance_identified(cl: dict) -> list[str] | None:
    """Names of the contact parameters the clearance fit identified (free, not at a bound,
    identifiable by its 1σ); None when the fit lists no parameters (older results)."""
    params = cl.get("parameters")
    if not isinstance(params, list) or not params:
        return None
    return [str(p.get("name")) for p in params if isinstance(p, dict) and p.get("free", True)
            and p.get("identifiable") and not p.get("at_bound")]


def clearance_not_identified(cl: dict) -> str:
    """The clearance section's lead when the fit identified nothing: what was fitted, why none of it
    is a finding, and what the numbers are then good for ("" when something was identified)."""
    names = clearance_identified(cl)
    if names is None or names:
        return ""
    params = [p for p in cl["parameters"] if isinstance(p, dict) and p.get("free", True)]
    rows = []
    for p in params:
        sd = p.get("std_error")
        spread = (f"± {fmt(100 * float(sd), 2)} %" if isinstance(sd, (int, float)) and "relative" in
                  str(p.get("std_error_kind", "")) else (f"± {fmt(sd, 2)}" if isinstance(sd, (int, float)) else "—"))
        state = "at its bound" if p.get("at_bound") else "not identifiable"
        unit = str(p.get("unit") or "")
        unit = "" if unit in ("1", "-", "–") else unit
        rows.append(f"<li>{esc(p.get('name'))} = {fmt(p.get('value'), 3)}{(' ' + esc(unit)) if unit else ''} "
                    f"({spread}, {state})</li>")
    agree, rigid = cl.get("agreement"), cl.get("rigid_agreement")
    gain = ""
    if isinstance(agree, (int, float)) and isinstance(rigid, (int, float)):
        gain = (f" Eq. 4.1 agreement with the gyro record is {fmt(agree, 3)} with the play and {fmt(rigid, 3)} for a "
                "rigid link: the play adds little that the record can see.")
    return ('<h3 id="clearance-not-identified">The clearance fit identified nothing from this record</h3>'
            '<p class="warn" role="note">The optimiser stopped normally ("converged" means only that its step '
            "and function tolerances were met), but none of the contact parameters is identified: each is at a "
            "bound of its range or has a standard error larger than its value. The numbers below are where the "
            "search stopped, not properties of the rig; the shaped predictions rest on the identified drive and "
            f"link mode, not on them.{gain}</p><ul>" + "".join(rows) + "</ul>")


def _uncalibrated_flank(n: float, play: float, md_without, f_link: float, z_link: float) -> str:
    """What a shaper on the identified link mode can leave on a rig not calibrated to the thesis: the
    fitted flank's own shape (n) and its play against the unshaped residual, from results.json."""
    mode = (f"The linear shapers are designed on the link mode identified from the gyro's free response "
            f"({fmt(f_link, 3)} Hz, ζ = {fmt(z_link, 2)})")
    if abs(n - 1.0) < 0.1:
        return mode + ("; the fitted flank is nearly linear, so that mode is the fitted model's vibration, and "
                       "what the rig's joint does beyond the fit a shaper on that mode leaves.")
    txt = mode + f"; the fitted flank is not linear (n = {fmt(n, 3)}, stiffer as it is pressed)"
    if isinstance(md_without, (int, float)) and md_without > 0:
        txt += (f" and its play of {fmt(play, 3)}° is {fmt(play / md_without, 2)}× the unshaped residual "
                f"({fmt(md_without, 3)}°)")
    return txt + (", so the ringing changes with the amplitude and with where the link rests in the play; one mode "
                  "describes it only in part, and a shaper on that mode can help, do nothing or hurt — the "
                  "improvements' intervals say which.")


def flank_discussion(ctx: Context, results: dict) -> str:
    """Why the calibrated contact is a soft, lightly damped flank rather than the thesis's stiff
    Hertzian law, and what that means for the shaped predictions — every number from results.json."""
    cl = ctx.sections.get("clearance")
    lm = ctx.sections.get("link_mode")
    if not isinstance(cl, dict) or not isinstance(lm, dict) or not lm.get("available", True):
        return ""
    unidentified = clearance_not_identified(cl)
    if unidentified:
        return unidentified
    try:
        k, d = float(cl["stiffness_n_m_per_rad_pow_n"]), float(cl["damping_n_m_s_per_rad"])
        n, j = float(cl["exponent"]), float(cl["link_inertia_kg_m2"])
        play = float(cl["play_deg"])
        f_link, z_link = float(lm["natural_frequency_hz"]), float(lm["damping_ratio"])
    except (KeyError, TypeError, ValueError):
        return ""
    w_link = 2 * math.pi * f_link
    th = _thesis_contact(results)
    md_without, md_with, tid = _rig_md(results)
    unit = "°" if ctx.mode == "position" else "°/s"
    p = []
    flank = (f"The study's clearance stage fits a contact of K = {fmt(k, 3)} N·m/rad<sup>n</sup>, "
             f"D = {fmt(d, 3)} N·m·s/rad, n = {fmt(n, 3)} and a total play of {fmt(play, 3)}° to the gyro record "
             f"(link inertia fixed at {fmt(j, 3)} kg·m²).")
    # "Soft" is a comparison, made only against a contact law the thesis gives: its K at least ten
    # times ours. A rig without the thesis's law (a what-if rig) gets the numbers, not the word.
    soft = bool(th.get("K")) and th["K"] > 10 * k
    if abs(n - 1.0) < 0.1:
        f_c = math.sqrt(k / j) / (2 * math.pi)
        flank += (f" That is a nearly linear{', soft' if soft else ''} flank: on the link alone it is a mode of "
                  f"√(K/J)/2π = "
                  f"{fmt(f_c, 3)} Hz with ζ = D/(2√(KJ)) = {fmt(d / (2 * math.sqrt(k * j)), 2)}. The link's residual "
                  f"mode, identified independently from the gyro's free response, is {fmt(f_link, 3)} Hz, "
                  f"ζ = {fmt(z_link, 2)}")
        flank += (" — the same mode." if abs(f_c / f_link - 1) <= 0.1 else
                  f" — the flank's mode combined with the drive's own dynamics ({fmt(f_link / f_c, 2)}× its "
                  "frequency).")
    else:
        flank += f" The exponent n = {fmt(n, 3)} makes the flank nonlinear (stiffer as it is pressed)."
    p.append(flank)
    # A built-in what-if rig documents its joint (results.json rig.documented): say where the fit misses it.
    doc_n, doc_play = tbl.num(ctx.documented.get("contact_exponent")), tbl.num(ctx.documented.get("play_deg"))
    missed = []
    if doc_n is not None and abs(n - doc_n) > 0.1:
        missed.append(f"its contact exponent is n = {fmt(doc_n, 3)}, the fit's n = {fmt(n, 3)}")
    if doc_play is not None and abs(play - doc_play) > 0.25 * doc_play:
        missed.append(f"its total play is {fmt(doc_play, 3)}°, the fit's {fmt(play, 3)}°")
    if missed:
        p.append("This rig's documented joint differs from the fit: " + "; ".join(missed) + ". The gyro record "
                 "this fit sees does not determine those parameters, so the fitted flank is an effective "
                 "description of the ringing it shows, not the rig's joint.")
    if th.get("K") and th.get("D"):
        n_th = th.get("n", 1.5)
        zeta_th = th["D"] / (2 * j * w_link)
        stiff = "a stiff Hertzian one" if th["K"] > 10 * k else "a Hertzian one"
        txt = (f"The thesis's own contact law is {stiff}, K = {fmt(th['K'], 3)}, n = {fmt(n_th, 3)}, "
               f"D = {fmt(th['D'], 3)} (units and link inertia unstated). Read in our units and with our link inertia, "
               f"its damping alone would be D/(2Jω) = {fmt(zeta_th, 3)} times critical at the {fmt(f_link, 3)} Hz "
               "mode")
        txt += (": the link would be locked to the motor, follow the drive's well-damped response and leave no "
                "residual ringing for Eq. 5.1 to measure." if zeta_th > 1 else ".")
        p.append(txt)
    if md_without is not None and ctx.calibrated:
        txt = (f"Why the calibration lands on a springy flank: the rig's truth is calibrated to the thesis's "
               f"<em>unshaped</em> mean deviations (Table {esc(tid)}: ours {fmt(md_without, 3)} {unit})"
               + (", which grow in proportion to the step (B.3, B.2, B.1) — the signature of a lightly damped linear "
                  "mode ringing after the move, not of impacts in a gap" if ctx.mode == "position" else
                  ", which need the link to keep ringing for several cycles after the step (Fig. 5.8)")
               + ". Only a soft, lightly damped contact rings like that; the thesis's K and D, taken at face value, "
               "cannot.")
        p.append(txt)
    trust = ("What it means for the shaped predictions: the calibration saw only unshaped responses, so every "
             "shaped number is a prediction of a model whose vibration is essentially one linear mode — the case "
             "input shaping is exact for. The play is the model's only nonlinearity")
    if md_without is not None and md_with is not None and ctx.mode == "position":
        trust += f": the fitted play is {fmt(play / md_without, 2)}× the unshaped residual ({fmt(md_without, 3)}°)"
        if play >= 0.5 * md_with:
            trust += (f" but {fmt(play / md_with, 2)}× the shaped one ({fmt(md_with, 3)}°), so the shaped mean "
                      "deviations are set by the play and the gyro's drift rather than by the mode")
        else:
            trust += (f" and {fmt(play / md_with, 2)}× even the shaped one ({fmt(md_with, 3)}°), so the model is "
                      "linear at every amplitude the tables measure, and the shaped mean deviations are set by the "
                      "gyro's drift and what the shaper leaves of the mode")
    if ctx.calibrated:
        trust += (". If the real contact is the stiff, impacting law the thesis identified, its vibration depends on "
                  "amplitude and each impact excites a broad band that a shaper tuned to one mode cannot cancel: the "
                  "shaped mean deviations and improvements here are then the best case for the modelled physics, and "
                  "their agreement with the thesis's shaped trials says that the thesis's rig, too, behaved as a "
                  "lightly damped mode as seen by its gyroscope — not that its contact law was soft.")
        head = "The calibrated flank: soft and lightly damped, unlike the thesis\'s contact law"
    else:
        trust = ("What it means for the shaped predictions: this rig is not calibrated to the thesis, so nothing "
                 "here was tuned to any measurement and the shaped numbers are predictions for this rig alone; "
                 "they are not compared with the thesis's shaped trials. " + _uncalibrated_flank(n, play, md_without,
                                                                                               f_link, z_link))
        head = "The fitted flank: what the gyro record shows of this rig's joint"
    p.append(trust)
    return f"<h3>{head}</h3>" + "".join(f"<p>{x}</p>" for x in p)


def shapers_html(ctx: Context) -> str:
    """The shapers the study designed (impulses), and those it could not design, once, with the reason."""
    sh = ctx.sections.get("shapers")
    if not isinstance(sh, list) or not sh:
        return ""
    designed, unavailable = [], {}
    for s in sh:
        if not isinstance(s, dict):
            continue
        imps = s.get("impulses") or []
        if s.get("unavailable") or not imps:
            unavailable.setdefault(str(s.get("unavailable") or "no impulses were designed"), []).append(
                str(s.get("key", "")))
            continue
        designed.append({"key": s.get("key", ""), "times": ", ".join(fmt(i.get("time_s")) for i in imps),
                         "amplitudes": ", ".join(fmt(i.get("amplitude")) for i in imps),
                         "duration": fmt(s.get("duration_s"))})
    return str(parts().shapers(designed, list(unavailable.items())))


def ambiguities_html(amb) -> str:
    if isinstance(amb, dict):
        amb = [{"title": k, **(v if isinstance(v, dict) else {"settled": v})} for k, v in amb.items()]
    items = []
    for a in amb or []:
        if not isinstance(a, dict):
            items.append({"anchor": f"ambiguity-{slug(a)}", "title": str(a), "lines": []})
            continue
        title = a.get("question") or a.get("title") or a.get("id") or "ambiguity"
        lines = [(lab, str(a[key])) for key, lab in (("settled", "Settled"), ("why", "Why"), ("reason", "Why"),
                                                      ("effect", "Effect"), ("reference", "Reference")) if a.get(key)]
        items.append({"anchor": f"ambiguity-{slug(a.get('id', title))}", "title": str(title), "lines": lines})
    return str(parts().ambiguities(items))


def comparison_rows(rows: list[tuple[str, tbl.Comparison]], reasons: bool = True) -> str:
    """One line of numbers per compared quantity, and below it the criterion and the reason."""
    out = []
    for sec, c in rows:
        unit = unit_text(c.unit)
        cls, text = (("na", "not compared") if c.agrees is None else ("ok", "agrees") if c.agrees
                     else ("diff better", "differs (ours better)") if ours_better(c) else ("diff", "differs"))
        compared = c.agrees is not None  # no Δ under "not compared": it would read as a verdict
        out.append({"where": f"{SECTION_TITLES.get(sec, sec)} · "
                             f"{('Table ' + c.table) if is_thesis_table(c.table) else ('clearshape table ' + c.table)}",
                    "quantity": c.quantity, "ours": Markup(with_unit(c.ours, unit)),
                    "thesis": Markup(thesis_num(c.thesis, c.thesis_text) + (f" {esc(unit)}" if unit and c.thesis
                                                                            is not None else "")), "diff": fmt_signed(c.diff) if compared else "—", "rel": fmt_pct(c.rel) if compared else "—",
                    "verdict_class": cls, "verdict": text, "criterion": c.criterion,
                    "why": c.why if reasons else ""})
    return str(parts().comparisons(out))


def differences_html(all_comps: list[tuple[str, tbl.Comparison]], ctx: Context | None = None) -> str:
    comps = [(s, c) for s, c in all_comps if c.thesis is not None]
    if not comps:
        return '<p class="empty">No number of this study has a published thesis value to compare with.</p>'
    if ctx is not None and not ctx.scored:
        return (f"<p>{len(comps)} published numbers beside ours, <strong>not scored</strong>: the rig is "
                f"{esc(ctx.rig_summary or ctx.rig_kind)} Agreeing or differing with the thesis would say nothing "
                "about either.</p><h3>For scale</h3>" + comparison_rows(comps))
    agree = [x for x in comps if x[1].agrees]
    differ = [x for x in comps if x[1].agrees is False]
    other = [x for x in comps if x[1].agrees is None]
    out = [f"<p>{len(comps)} published numbers compared: <strong>{len(agree)} agree</strong>, "
           f"<strong>{len(differ)} differ</strong>, {len(other)} not comparable. "
           "Means of repeated trials agree when their difference is within twice the standard error of the "
           "difference of the two means (not one trial's s.d.); improvements when the seeded 95 % bootstrap "
           "interval of ours − thesis contains 0; other numbers when within 10 %. Thesis numbers are quoted as "
           "printed. Tables the thesis prints twice (5.2 = B.1 + B.5; B.6 = the improvements of B.1–B.5) are "
           "counted once.</p>"]
    if differ:
        out.append("<h3>Where clearshape differs</h3>" + comparison_rows(differ))
    if agree:
        out.append("<h3>Where clearshape agrees</h3>" + comparison_rows(agree))
    if other:
        out.append("<h3>Not comparable</h3>" + comparison_rows(other))
    return "".join(out)


def dedupe(comps: list) -> list[tuple[str, tbl.Comparison]]:
    """Each published number once: a number the thesis prints twice (Table 5.2 = B.1 + B.5, B.6 = the
    improvements of B.1–B.5) is kept from its trial table, whose verdict uses the trials' spread."""
    def rank(item):
        _, c, composite = item
        return (1 if composite else 0, 0 if c.kind in ("mean", "improvement") and c.column is not None
                and c.column.thesis and len(c.column.thesis) > 1 else 1)
    ordered = sorted(enumerate(comps), key=lambda x: (rank(x[1]), x[0]))
    seen, keep = set(), set()
    for i, (_, c, _) in ordered:
        key = (c.kind if c.kind != "parameter" else c.quantity, None if c.ours is None else round(c.ours, 9))
        if c.ours is not None and key in seen:
            continue
        seen.add(key)
        keep.add(i)
    return [(s, c) for i, (s, c, _) in enumerate(comps) if i in keep]


def shaped_results(tables: list[tbl.Table]) -> list[dict]:
    """Every shaped column of the rig's trial tables: its improvement, bootstrap interval and the thesis's
    printed improvement (composite tables, which repeat other tables' columns, left out)."""
    ids = {t.id for t in tables}
    out = []
    for t in tables:
        if not t.is_trials or t.kind != "mean-deviation" or section_of_table(t) != "rig" or is_composite(t, ids):
            continue
        for c in t.columns:
            if c.unshaped or c.improvement is None:
                continue
            ci = c.improvement_ci if c.improvement_ci and not isinstance(c.improvement_ci[0], list) else None
            out.append({"table": t.id, "label": c.label, "ours": c.improvement, "ci": ci,
                        "noise": bool(ci) and ci[0] <= 0.0 <= ci[1], "thesis": c.thesis_improvement,
                        "thesis_text": c.thesis_improvement_printed, "column": c})
    return out


def _result_item(r: dict, comp: tbl.Comparison | None) -> str:
    thesis = ""
    if r["thesis"] is not None:
        thesis = f" (thesis {thesis_num(r['thesis'], r['thesis_text'])} %"
        thesis += f"; {esc(comp.criterion)})" if comp is not None and comp.agrees is not None else ")"
    return f"<li>Table {esc(r['table'])}, {esc(r['label'])}: {improvement_html(r['ours'], r['ci'])}{thesis}</li>"


def reach_sentences(tables: list[tbl.Table]) -> list[str]:
    """The measurement floor's sentences ("What a command can reach here"), one per rig table."""
    t = next((x for x in tables if x.kind == "reach"), None)
    if t is None:
        return []
    return [str(v.get("sentence")) for v in t.headline.values() if isinstance(v, dict) and v.get("sentence")]


def headline_html(all_comps: list[tuple[str, tbl.Comparison]], ctx: Context, tables: list[tbl.Table]) -> str:
    """The finding, at the top of the page: what was reproduced, what was not, what is within noise and
    what is worse than unshaped, with every count of the comparison (not comparable ones included)."""
    comps = [c for _, c in all_comps if c.thesis is not None]
    results = shaped_results(tables)
    by_col = {id(c.column): c for c in comps if c.kind == "improvement" and c.column is not None}
    groups = []
    if ctx.scored:
        groups += [("Reproduced", "reproduced",
                    [r for r in results if by_col.get(id(r["column"])) and by_col[id(r["column"])].agrees]),
                   ("Not reproduced", "not-reproduced",
                    [r for r in results if by_col.get(id(r["column"])) and by_col[id(r["column"])].agrees is False])]
    groups += [("Within noise (the 95 % interval holds 0)", "noise", [r for r in results if r["noise"]]),
               ("Worse than unshaped", "worse", [r for r in results if r["ours"] < 0])]
    if not ctx.scored:
        groups.insert(0, ("Improvements on this rig (not scored against the thesis)", "rig-results",
                          [r for r in results if not r["noise"] and r["ours"] >= 0]))
    out = ['<div class="summary" id="finding"><h2>Finding</h2>']
    out.append(f'<p class="rig-line">{rig_note(ctx)}</p>')
    for title, cls, rows in groups:
        if not rows:
            continue
        items = "".join(_result_item(r, by_col.get(id(r["column"]))) for r in rows)
        out.append(f'<p class="finding {cls}"><strong>{esc(title)}:</strong></p><ul class="finding {cls}">{items}</ul>')
    agree = sum(1 for c in comps if c.agrees)
    differ = sum(1 for c in comps if c.agrees is False)
    other = sum(1 for c in comps if c.agrees is None)
    if ctx.scored:
        line = (f"{len(comps)} published numbers compared with the thesis: {agree} agree, {differ} differ, "
                f"{other} not comparable (<a href=\"#differences\">details</a>).")
    else:
        line = (f"Not scored against the thesis: {len(comps)} published numbers are shown beside ours for scale "
                "(<a href=\"#differences\">list</a>).")
    out.append(f"<p>{line}</p>")
    identity: dict[str, list[str]] = {}
    for r in results:
        if str(r["column"].note).startswith("identity shaper"):
            identity.setdefault(r["label"], []).append(r["table"])
    if identity:
        named = "; ".join(f"{lab} (Table{'s' if len(ts) > 1 else ''} {', '.join(ts)})" for lab, ts in identity.items())
        out.append("<p><strong>The thesis's own design does nothing here:</strong> "
                   + esc(named) + " is the identity (one impulse: the drive model has ζ ≈ 1), so "
                   "its trials are unshaped trials again and their 'improvement' is noise; the gains above come "
                   "from the design for the link's identified mode.</p>")
    sources = sorted({r["column"].source for r in results if r["thesis"] is not None and r["column"].source})
    if sources and sources != ["drive-model"]:
        out.append("<p>The thesis designed its shapers from its drive model (§3.3); its shaped numbers stand "
                   f"beside clearshape's {esc(', '.join(sources))} design, which is a different shaper.</p>")
    reach = reach_sentences(tables)
    if reach:
        out.append('<p><strong>What a command can reach here</strong> (the measurement floor, '
                   '<a href="#table-reach">table</a>):</p><ul class="reach">'
                   + "".join(f"<li>{esc(x)}</li>" for x in reach) + "</ul>")
    out.append("</div>")
    return "".join(out)


# ----------------------------------------------------------------------------------------------
# The page


def build(study_dir: Path, records: list[dict] | None = None, output: Path | None = None) -> Path:
    study_dir = Path(study_dir)
    results = read_json(study_dir / "results.json")
    ctx = Context(results)
    if records is None:
        index = read_json(study_dir / "figures.json") if (study_dir / "figures.json").exists() else {}
        specs = list(index.get("figures", []) or [])
        extra = md_summary_spec(results)
        if extra and not any(str(f.get("kind")) == "md-summary" for f in specs):
            specs.append(extra)
        records = []
        for i, spec in enumerate(specs):
            fid = figure_id(spec, i)
            png, pdf = study_dir / "figures" / f"{fid}.png", study_dir / "figures" / f"{fid}.pdf"
            records.append({"id": fid, "spec": spec, "png": png if png.exists() else None,
                            "pdf": pdf if pdf.exists() else None,
                            "error": None if png.exists() else "not drawn (run python/render_study.py)"})

    tables = [tbl.normalise(t) for t in results.get("tables", []) or [] if isinstance(t, dict)]
    tables_by_sec: dict[str, list] = {s: [] for s in SECTION_IDS}
    for t in tables:
        tables_by_sec[section_of_table(t)].append(t)
    figs_by_sec: dict[str, list] = {s: [] for s in SECTION_IDS}
    for i, rec in enumerate(records):
        figs_by_sec[section_of_figure(rec["spec"])].append((i, rec))

    all_comps: list[tuple[str, tbl.Comparison]] = []
    fig_counter = [0]
    table_ids = {t.id for t in tables}
    spreads = improvement_spreads(tables)
    order = {id(t): i for i, t in enumerate(tables)}

    def figures(sec: str) -> str:
        items = sorted(figs_by_sec[sec], key=lambda x: (thesis_number_key(x[1]["spec"].get("thesis_figure")), x[0]))
        out = []
        for _, rec in items:
            fig_counter[0] += 1
            out.append(render_figure(rec, fig_counter[0]))
        return "".join(out)

    def tables_html(sec: str) -> str:
        out = []
        for t in sorted(tables_by_sec[sec], key=lambda t: (thesis_number_key(t.id), order[id(t)])):
            comps = comparisons_of(ctx, t, spreads)
            composite = is_composite(t, table_ids)
            out.append(render_table(t, comps, composite))
            all_comps.extend((sec, c, composite) for c in comps)
        return "".join(out)

    body = []
    body.append(section("setup", setup_html(ctx, study_dir, records)))
    for sec in ("consistency", "identification", "clearance", "simulated", "rig"):
        pre = ""
        if sec == "identification":
            pre = identification_facts(ctx)
        elif sec == "clearance":
            pre = clearance_facts(ctx) + flank_discussion(ctx, results)
        elif sec == "simulated":
            pre = shapers_html(ctx)
        if sec == "rig":  # the summary figure first, then the tables, then the traces
            summary = [r for _, r in figs_by_sec["rig"] if r["spec"].get("kind") == "md-summary"]
            figs_by_sec["rig"] = [(i, r) for i, r in figs_by_sec["rig"] if r["spec"].get("kind") != "md-summary"]
            lead = []
            for r in summary:
                fig_counter[0] += 1
                lead.append(render_figure(r, fig_counter[0]))
            content = "".join(lead) + tables_html(sec) + figures(sec)
        else:
            content = pre + tables_html(sec) + figures(sec)
        body.append(section(sec, content, f"Not produced by this {ctx.mode or ''}-mode study (make run writes "
                                          "both modes' reports)."))
    all_comps = dedupe(all_comps)
    body.append(section("ambiguities", ambiguities_html(results.get("ambiguities"))))
    body.append(section("differences", differences_html(all_comps, ctx)))

    page = page_html(ctx, body, headline_html(all_comps, ctx, tables), records)
    output = Path(output) if output else study_dir / "report.html"
    tmp = output.with_name(output.name + ".tmp")
    tmp.write_text(page, encoding="utf-8")
    tmp.replace(output)  # atomic: a reader sees the old page or the new one, never half of one
    return output





def page_html(ctx: Context, sections: list[dict], headline: str, records: list[dict]) -> str:
    st = ctx.study
    return TEMPLATES.get_template("report.html.j2").render(
        study_name=st.get("name") or "clearshape study", study_title=st.get("title") or "",
        headline=Markup(headline), sections=sections, figures_expected=len(records),
        figures_drawn=sum(1 for r in records if not r.get("error")),
        css=Markup((TEMPLATE_DIR / "report.css").read_text(encoding="utf-8")),
        script=Markup((TEMPLATE_DIR / "report.js").read_text(encoding="utf-8")))


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 1 or argv[0] in ("-h", "--help"):
        print("usage: make_report.py <study-output-folder>", file=sys.stderr)
        return 2
    try:
        path = build(Path(argv[0]))
    except StudyDataError as e:
        print(f"make_report: {e}", file=sys.stderr)
        return 2
    print(path.resolve())
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
