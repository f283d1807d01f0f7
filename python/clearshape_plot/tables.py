"""Tables of results.json (docs/study-outputs.md) and their comparison with the thesis.

A results table is column-oriented: id, kind (consistency, mean-deviation, parameters, matrix,
improvement), title, unit, row_labels, note, and columns — each with key, label, ``ours`` and/or
``thesis`` (one value per row label, or per trial: the thesis always has its 10 trials, a quick
study fewer), ``ours_mean``/``ours_std``/``thesis_mean`` and, for shaped columns,
``improvement_percent``/``thesis_improvement_percent``.

Verdicts. A mean of repeated trials *agrees* with the thesis's when the difference is within twice
the standard error of the difference of the two means, √(s²/n + s_t²/n_t) (the two sets of trials
are not distinguishable at about 95 %), not within one trial's s.d. An improvement % agrees when
the seeded 95 % bootstrap interval of ours − thesis (results.json
``improvement_difference_ci95_percent``) contains 0. Other numbers (identified parameters,
agreement figures) agree within 10 % of the thesis's value. Every verdict carries its criterion.

Thesis numbers are the ones the thesis printed: ``thesis_improvement_percent`` is the printed
improvement (null where it printed none; ``thesis_improvement_recomputed_percent`` is the value
recomputed from its means, never shown as the thesis's), and ``thesis_printed`` /
``thesis_mean_printed`` / ``thesis_improvement_printed`` give its digits as printed (0.270, 0.0009).
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from . import roles

DEFAULT_REL_TOLERANCE = 0.10
TRIAL_KINDS = {"consistency", "mean-deviation"}


def num(v):
    """A finite float, or None."""
    if v is None or isinstance(v, bool):
        return None
    if isinstance(v, dict):
        for k in ("value", "mean", "ours"):
            if k in v:
                return num(v[k])
        return None
    try:
        f = float(v)
    except (TypeError, ValueError):
        return None
    return f if math.isfinite(f) else None


def nums(v) -> list:
    return [num(x) for x in v] if isinstance(v, list) else []


@dataclass
class Column:
    key: str
    label: str
    ours: list = field(default_factory=list)
    thesis: list = field(default_factory=list)
    ours_std: list | None = None  # per row (parameter tables)
    ours_mean: float | None = None
    ours_sd: float | None = None  # over trials
    thesis_mean: float | None = None
    improvement: float | None = None
    thesis_improvement: float | None = None
    note: str = ""
    extra: dict = field(default_factory=dict)  # other per-row arrays (e.g. delay_s)
    raw: dict = field(default_factory=dict)
    # 95 % bootstrap interval of our improvement [lo, hi] (per row in an improvement table)
    improvement_ci: list | None = None
    thesis_improvement_recomputed: float | None = None  # from the thesis's means, not printed by it
    difference_ci: list | None = None  # bootstrap interval of ours − thesis (improvement)
    thesis_printed: list = field(default_factory=list)  # the thesis's digits, per row
    thesis_mean_printed: str | None = None
    thesis_improvement_printed: str | None = None

    def thesis_text(self, i: int) -> str | None:
        """Row i's thesis number as the thesis printed it (None when there is none)."""
        if i < len(self.thesis_printed) and isinstance(self.thesis_printed[i], str):
            return self.thesis_printed[i]
        return None

    @property
    def role(self) -> str:
        k = self.key.split(":")[-1]
        return k.split("@")[0].lower()

    @property
    def source(self) -> str:
        k = self.key.split(":")[-1]
        return k.split("@")[1] if "@" in k else ""

    @property
    def unshaped(self) -> bool:
        return self.role in ("none", "unshaped", "without")


@dataclass
class Table:
    id: str
    kind: str
    title: str
    unit: str
    row_labels: list
    columns: list
    note: str = ""
    headline: dict = field(default_factory=dict)
    raw: dict = field(default_factory=dict)

    @property
    def is_trials(self) -> bool:
        """Rows are repeated trials (labels 1, 2, …)."""
        return self.kind in TRIAL_KINDS and bool(self.row_labels) and all(
            re.fullmatch(r"\d+", str(r)) for r in self.row_labels)

    def column(self, key: str):
        return next((c for c in self.columns if c.key == key), None)


_KNOWN = {"key", "label", "ours", "thesis", "input", "ours_std", "ours_mean", "thesis_mean", "improvement_percent",
          "thesis_improvement_percent", "note", "shaper", "thesis_std", "improvement_ci95_percent",
          "improvement_significant", "thesis_improvement_recomputed_percent", "thesis_improvement_ci95_percent",
          "improvement_difference_ci95_percent", "thesis_printed", "thesis_mean_printed",
          "thesis_improvement_printed"}


def interval(v):
    """A [lo, hi] pair of finite numbers, or None."""
    if isinstance(v, list) and len(v) == 2 and all(num(x) is not None for x in v):
        return [num(v[0]), num(v[1])]
    return None


def plain_label(text: str) -> str:
    """"without is" / "with is" (input shaping) spelled so it cannot read as the verb: "without IS"."""
    return re.sub(r"\b([Ww]ith|[Ww]ithout) is\b", lambda m: f"{m.group(1)} IS", text)


def normalise(t: dict) -> Table:
    rows = [str(r) for r in (t.get("row_labels") or [])]
    cols = []
    for c in t.get("columns", []) or []:
        if not isinstance(c, dict):
            continue
        key = str(c.get("key") or c.get("label"))
        std = c.get("ours_std")
        col = Column(key=key, label=plain_label(str(c.get("label") or key)), ours=nums(c.get("ours")),
                     thesis=nums(c.get("thesis")), ours_std=nums(std) if isinstance(std, list) else None,
                     ours_mean=num(c.get("ours_mean")), ours_sd=num(std) if not isinstance(std, list) else None,
                     thesis_mean=num(c.get("thesis_mean")), improvement=num(c.get("improvement_percent")),
                     thesis_improvement=num(c.get("thesis_improvement_percent")), note=str(c.get("note") or ""),
                     raw=c)
        if not any(v is not None for v in col.thesis):  # a thesis column with no value is no thesis column
            col.thesis = []
        ci = c.get("improvement_ci95_percent")
        col.improvement_ci = ([interval(x) for x in ci] if isinstance(ci, list) and ci and isinstance(ci[0], list)
                              or (isinstance(ci, list) and ci and ci[0] is None) else interval(ci))
        col.thesis_improvement_recomputed = num(c.get("thesis_improvement_recomputed_percent"))
        col.difference_ci = interval(c.get("improvement_difference_ci95_percent"))
        tp = c.get("thesis_printed")
        col.thesis_printed = list(tp) if isinstance(tp, list) else []
        col.thesis_mean_printed = c.get("thesis_mean_printed") if isinstance(c.get("thesis_mean_printed"), str) else None
        tip = c.get("thesis_improvement_printed")
        col.thesis_improvement_printed = tip if isinstance(tip, str) else None
        col.extra = {k: nums(v) for k, v in c.items() if k not in _KNOWN and isinstance(v, list)
                     and v and all(isinstance(x, (int, float)) or x is None for x in v)}
        cols.append(col)
    note = " ".join(x for x in [str(t.get("note") or "")] + [delays_that_apply(c) for c in cols] if x)
    return Table(id=str(t.get("id", "")), kind=str(t.get("kind", "")), title=str(t.get("title", "")),
                 unit=str(t.get("unit", "") or ""), row_labels=rows, columns=cols, note=note,
                 headline=t.get("headline") if isinstance(t.get("headline"), dict) else {}, raw=t)


def delay_applies(delay_s: float | None, duration_s: float | None) -> bool:
    """A shaper's half-rise delay (metrics::shaping_delay_s) measures what the shaper adds only when it
    lies in (0, duration]: a positive shaper's impulses spread a step over its duration, so its response
    reaches half the final value later, by no more than that. 0 or more than the duration means half
    the final value is reached on another step of the input (a double step, a PRBS), not delayed."""
    if delay_s is None:
        return False
    return delay_s > 0 and (duration_s is None or delay_s <= duration_s * (1 + 1e-9))


def delays_that_apply(col: Column) -> str:
    """Keeps a column's delay_s only where it applies (delay_applies): the unshaped reference has none
    (0 by definition), a shaped input where it does not apply reads "—". Returns the note that says so."""
    if "delay_s" not in col.extra:
        return ""
    if col.key in ("none", "unshaped") or roles.normalise_role(col.key) == "unshaped":
        del col.extra["delay_s"]
        return ""
    duration = num(col.raw.get("shaper_duration_s"))
    kept = [d if delay_applies(d, duration) else None for d in col.extra["delay_s"]]
    if kept == col.extra["delay_s"]:
        return ""
    col.extra["delay_s"] = kept
    if all(d is None for d in kept):
        del col.extra["delay_s"]
    span = f"the shaper's duration, {duration:.3g} s" if duration is not None else "the shaper's duration"
    return (f"{col.label}: a delay is given only where it lies between 0 and {span}; \u2014 where the input "
            "reaches half its final value on another of its steps, so the half-rise time measures no delay.")


def mean_sd(values):
    v = [x for x in values if x is not None]
    if not v:
        return None, None
    m = sum(v) / len(v)
    s = math.sqrt(sum((x - m) ** 2 for x in v) / (len(v) - 1)) if len(v) > 1 else None
    return m, s


_SUP = str.maketrans("-0123456789", "\u207b\u2070\u00b9\u00b2\u00b3\u2074\u2075\u2076\u2077\u2078\u2079")


def g3(v: float) -> str:
    """3 significant digits as the tables print numbers: ×10ⁿ, never "e-05", and the minus sign U+2212."""
    s = f"{v:.3g}"
    if "e" in s:
        mant, exp = s.split("e")
        s = f"{mant}×10{str(int(exp)).translate(_SUP)}"
    return s.replace("-", "\u2212")


def verdict(ours, thesis, spread=None, spread_name="", rel_tol=DEFAULT_REL_TOLERANCE) -> dict:
    """Difference, relative difference and agrees/differs with the criterion used."""
    if thesis is None:
        return {"diff": None, "rel": None, "agrees": None, "criterion": "the thesis has no value"}
    if ours is None:
        return {"diff": None, "rel": None, "agrees": None, "criterion": "no value from the study"}
    diff = ours - thesis
    rel = diff / abs(thesis) if thesis != 0 else None
    # The criterion states what was found, so a failing line never reads as if it held.
    if spread:
        ok = abs(diff) <= spread
        return {"diff": diff, "rel": rel, "agrees": ok,
                "criterion": f"|Δ| = {g3(abs(diff))} {'≤' if ok else '>'} {spread_name} ({g3(spread)})"}
    if rel is None:
        return {"diff": diff, "rel": None, "agrees": False,
                "criterion": f"the thesis value is 0: no relative criterion, |Δ| = {g3(abs(diff))}"}
    ok = abs(rel) <= rel_tol
    return {"diff": diff, "rel": rel, "agrees": ok,
            "criterion": f"|Δ| = {g3(100 * abs(rel))} % of the thesis value, {'≤' if ok else '>'} {100 * rel_tol:g} %"}


def standard_error_of_difference(ours: list, thesis: list):
    """√(s²/n + s_t²/n_t) of the difference of two means of trials; None with fewer than 2 of either."""
    o, t = [x for x in ours if x is not None], [x for x in thesis if x is not None]
    if len(o) < 2 or len(t) < 2:
        return None
    return math.sqrt(mean_sd(o)[1] ** 2 / len(o) + mean_sd(t)[1] ** 2 / len(t))


def interval_verdict(ours, thesis, ci) -> dict:
    """An improvement against the thesis's: agrees when the bootstrap interval of ours − thesis holds 0."""
    v = verdict(ours, thesis)
    if v["diff"] is None or ci is None:
        return v
    ok = ci[0] <= 0.0 <= ci[1]
    v["agrees"] = ok
    span = f"[{ci[0]:.1f}, {ci[1]:.1f}]".replace("-", "−")
    v["criterion"] = (f"95 % bootstrap interval of Δ {span} {'contains' if ok else 'excludes'} 0"
                      f"{'' if ok else ': the difference is significant'}")
    return v


def thesis_improvement_sd(without: Column, with_: Column):
    """s.d. of the thesis's per-trial improvements 100·(1 − with_i/without_i) over its trial pairs."""
    pairs = [(u, w) for u, w in zip(without.thesis, with_.thesis) if u and w is not None]
    if len(pairs) < 2:
        return None
    return mean_sd([100.0 * (1.0 - w / u) for u, w in pairs])[1]


@dataclass
class Comparison:
    table: str
    quantity: str
    unit: str
    ours: float | None
    thesis: float | None
    diff: float | None
    rel: float | None
    agrees: bool | None
    criterion: str
    kind: str  # "mean", "improvement", "parameter"
    column: Column | None = None
    why: str = ""
    thesis_text: str | None = None  # the thesis's number as it printed it


def _cmp(table, quantity, unit, ours, thesis, kind, column=None, spread=None, spread_name="") -> Comparison:
    v = verdict(ours, thesis, spread, spread_name)
    return Comparison(table=table, quantity=quantity, unit=unit, ours=ours, thesis=thesis, kind=kind,
                      column=column, **v)


def compare_table(t: Table) -> list[Comparison]:
    """Every number of the table that the thesis also published, with a verdict."""
    out: list[Comparison] = []
    if t.is_trials:
        for c in t.columns:
            om = c.ours_mean if c.ours_mean is not None else mean_sd(c.ours)[0]
            tm = c.thesis_mean if c.thesis_mean is not None else mean_sd(c.thesis)[0]
            se = standard_error_of_difference(c.ours, c.thesis)
            if tm is not None or om is not None:
                out.append(_cmp(t.id, f"{c.label} — mean", t.unit, om, tm, "mean", c, 2 * se if se else None,
                                "2 × the standard error of the difference of the means"))
                out[-1].thesis_text = c.thesis_mean_printed if c.thesis_mean is not None else None
            if c.improvement is not None or c.thesis_improvement is not None:
                v = interval_verdict(c.improvement, c.thesis_improvement, c.difference_ci)
                out.append(Comparison(table=t.id, quantity=f"{c.label} — improvement", unit="%",
                                      ours=c.improvement, thesis=c.thesis_improvement, kind="improvement",
                                      column=c, thesis_text=c.thesis_improvement_printed, **v))
        return out
    if t.kind == "parameters":
        ours_col, thesis_col = parameter_pair(t)
        if ours_col is None or thesis_col is None:
            return out
        for i, row in enumerate(t.row_labels):
            o = ours_col.ours[i] if i < len(ours_col.ours) else None
            th = thesis_col.thesis[i] if i < len(thesis_col.thesis) else None
            if th is None:
                continue
            out.append(_cmp(t.id, row, "", o, th, "parameter", ours_col))
            out[-1].thesis_text = thesis_col.thesis_text(i)
        return out
    # Row-wise tables with ours and thesis in the same column (e.g. B.6).
    for c in t.columns:
        if not c.thesis:
            continue
        for i, row in enumerate(t.row_labels):
            o = c.ours[i] if i < len(c.ours) else None
            th = c.thesis[i] if i < len(c.thesis) else None
            if th is None:
                continue
            out.append(_cmp(t.id, f"{row}" + (f" — {c.label}" if len(t.columns) > 1 else ""), t.unit, o, th,
                            "improvement" if t.kind == "improvement" else "parameter", c))
            out[-1].thesis_text = c.thesis_text(i)
    return out


def parameter_pair(t: Table):
    """(our column to compare, the thesis's column) of a parameters table: ours is the column the
    headline selects, or labelled "(selected)", or keyed "ours", or the first with values."""
    thesis_col = next((c for c in t.columns if c.thesis and not c.ours), None)
    if thesis_col is None:
        thesis_col = next((c for c in t.columns if c.thesis), None)
    cands = [c for c in t.columns if c.ours]
    sel = t.headline.get("selected_input") if t.headline else None
    # Like with like: the thesis's model was identified from one input; ours from that input is the one
    # to compare with it, whichever model our cross-validation selected.
    same_input = thesis_col.raw.get("input") if thesis_col is not None else None
    ours_col = (next((c for c in cands if same_input and c.key == same_input), None)
                or next((c for c in cands if sel and c.key == sel), None)
                or next((c for c in cands if "(selected)" in c.label), None)
                or next((c for c in cands if c.key == "ours"), None)
                or (cands[0] if cands else None))
    return ours_col, thesis_col
