#!/usr/bin/python3
"""Checks of a rendered study report against issue 13's defects, one named check per call:

    /usr/bin/python3 tests/report/report_checks.py <check> <study-dir> <python-dir> [<repo-root>]

<study-dir> holds results.json, figures.json, data/ and report.html (python/render_study.py).
Prints what it compared; exit 0 when the check holds, 1 when it does not, 2 on bad usage.
Checks that need another study (another rig kind, a fit that identified nothing) rewrite a copy
of results.json in a temporary folder and render that copy; the study folder is never modified.
"""
from __future__ import annotations

import copy
import csv
import json
import math
import re
import shutil
import subprocess
import sys
import tempfile
from html.parser import HTMLParser
from pathlib import Path

FAILURES: list[str] = []


def expect(cond: bool, what: str) -> None:
    if not cond:
        FAILURES.append(what)


class Tables(HTMLParser):
    """Every <table>: id, class, and its rows as lists of (tag, text)."""

    def __init__(self):
        super().__init__()
        self.tables, self._stack, self._cell = [], [], None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "table":
            self._stack.append({"id": a.get("id", ""), "class": a.get("class", ""), "rows": [], "section": ""})
        elif tag == "tr" and self._stack:
            self._stack[-1]["rows"].append([])
        elif tag in ("td", "th") and self._stack:
            self._cell = [tag, "", int(a.get("colspan", "1"))]

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self._cell and self._stack and self._stack[-1]["rows"]:
            self._stack[-1]["rows"][-1].append((self._cell[0], self._cell[1].strip(), self._cell[2]))
            self._cell = None
        elif tag == "table" and self._stack:
            self.tables.append(self._stack.pop())

    def handle_data(self, data):
        if self._cell is not None:
            self._cell[1] += data


def tables_of(html: str) -> list[dict]:
    p = Tables()
    p.feed(html)
    return p.tables


def section(html: str, sid: str) -> str:
    start = html.find(f'<section id="{sid}"')
    end = html.find("</section>", start)
    return html[start:end] if start >= 0 else ""


def render_copy(study: Path, results: dict, tmp: Path) -> str:
    """Renders the report of a copy of the study with `results` as its results.json."""
    out = tmp / "study"
    if out.exists():
        shutil.rmtree(out)
    out.mkdir(parents=True)
    for name in ("figures.json",):
        if (study / name).exists():
            shutil.copy(study / name, out / name)
    for d in ("data", "figures"):
        if (study / d).is_dir():
            shutil.copytree(study / d, out / d)
    (out / "results.json").write_text(json.dumps(results), encoding="utf-8")
    import make_report  # noqa: E402
    return make_report.build(out).read_text(encoding="utf-8")


# ----------------------------------------------------------------------------------------------


def check_link_mode_fit(study: Path, results: dict, **_) -> None:
    """1. The fitted link mode is drawn where the gyro's free decay is: the fit's time axis starts at
    the analysed window, and there the fit and the gyro agree."""
    lm = results.get("sections", {}).get("link_mode", {})
    runs = [r for r in lm.get("runs", []) if "window_start_s" in r]
    path = study / "data" / "link_mode_fit.csv"
    if not runs or not path.exists():
        print("no link-mode fit in this study")
        return
    rows = list(csv.DictReader(path.open()))
    t0 = float(rows[0]["time_s"])
    gyro = [float(r["gyro_deg_s"]) for r in rows]
    fit = [float(r["fitted_deg_s"]) for r in rows]
    span = max(gyro) - min(gyro)
    rms = math.sqrt(sum((g - f) ** 2 for g, f in zip(gyro, fit)) / len(gyro))
    print(f"window start {runs[0]['window_start_s']} s, CSV starts {t0} s; fit − gyro at start "
          f"{fit[0] - gyro[0]:.3g}, RMS {rms:.3g} of a {span:.3g} span")
    expect(abs(t0 - float(runs[0]["window_start_s"])) < 1e-9, "link_mode_fit.csv does not start at the window")
    expect(abs(fit[0] - gyro[0]) <= 0.2 * span, "the fit and the gyro disagree at the window's start")
    expect(rms <= 0.2 * span, "the fitted mode does not follow the gyro record")


def check_clearance_identified(study: Path, results: dict, tmp: Path, **_) -> None:
    """2. A clearance fit that identified no parameter is not presented as a finding."""
    cl = results.get("sections", {}).get("clearance")
    if not isinstance(cl, dict) or not cl.get("parameters"):
        print("no clearance fit with parameters in this study")
        return
    r = copy.deepcopy(results)
    for p in r["sections"]["clearance"]["parameters"]:
        p["identifiable"] = False
        if p.get("name") == "play":
            p["at_bound"] = True
    html = section(render_copy(study, r, tmp), "clearance")
    expect("identified nothing" in html, "a fit without identified parameters is not said to have identified nothing")
    expect("The calibrated flank" not in html, "a fit without identified parameters is discussed as a finding")
    html = section((study / "report.html").read_text(encoding="utf-8"), "clearance")
    identified = [p["name"] for p in cl["parameters"] if p.get("identifiable") and not p.get("at_bound")]
    print(f"identified in this study: {identified or 'none'}")
    expect(("identified nothing" in html) == (not identified), "the report's verdict on the fit contradicts results.json")


def check_empty_columns(study: Path, results: dict, html: str, **_) -> None:
    """3. No table column is all "—"; a shaper that could not be designed is named with the reason."""
    bad = []
    for t in tables_of(html):
        if "results" not in t["class"] and "generic" not in t["class"]:
            continue
        body = [r for r in t["rows"] if r and r[0][0] == "th" and any(c[0] == "td" for c in r)]
        if len(body) < 2:
            continue
        width = min(len(r) for r in body)
        for j in range(1, width):
            cells = [r[j][1] for r in body]
            if all(c in ("—", "") for c in cells) and not all(c == "" for c in cells):
                bad.append(f"{t['id'] or t['class']} column {j}")
    print(f"columns with no value: {bad or 'none'}")
    expect(not bad, f"columns that hold only —: {bad[:6]}")
    for s in results.get("sections", {}).get("shapers", []) or []:
        if isinstance(s, dict) and s.get("unavailable"):
            expect(s["key"] in html and "Not designed" in html, f"{s['key']} is not named as not designed")
            reason = s["unavailable"].split(":")[0]
            expect(reason in html, f"the reason {reason!r} is not given")


def check_layout_1400(study: Path, html: str, python_dir: Path, **_) -> None:
    """4. No table too wide for the page at 1400 px or in print: each part of a table holds at most
    14 cells in a row (the page's column holds about that many numbers). Chromium's own layout of
    the page is checked by the report test from report_shots.py's layout.json."""
    widest = 0
    for t in tables_of(html):
        if "results" in t["class"] and t["rows"]:
            cells = max(sum(c[2] for c in r) for r in t["rows"])
            widest = max(widest, cells)
            expect(cells <= 14, f"table {t['id']} has {cells} cells in a row (too wide for the page)")
    print(f"widest results table: {widest} cells in a row")


def check_is_spelling(html: str, study: Path, **_) -> None:
    """5. "without is / with is" never reads as the verb."""
    text = html + (study / "figures.json").read_text(encoding="utf-8") if (study / "figures.json").exists() else html
    hits = re.findall(r".{0,30}\b[Ww]ith(?:out)? is\b.{0,20}", text)
    print(f"'with(out) is' found {len(hits)} times")
    expect(not hits, f"'without is' / 'with is' in the report: {hits[:3]}")


def _legend_clear_of_data(fig, ax) -> bool:
    """The axes' legend (if any) does not overlap the axes' data area."""
    fig.canvas.draw()
    leg = ax.get_legend()
    if leg is None or not ax.axison:  # a legend-only slot (axis off) holds no data
        return True
    r = fig.canvas.get_renderer()
    a, b = leg.get_window_extent(r), ax.get_window_extent(r)
    return not a.overlaps(b)


def plt_close(fig) -> None:
    import matplotlib.pyplot as plt  # noqa: E402
    plt.close(fig)


def _figures(study: Path, python_dir: Path):
    sys.path.insert(0, str(python_dir))
    from clearshape_plot import figures  # noqa: E402
    from clearshape_plot.data import CsvCache  # noqa: E402
    figures.use_style()
    return figures, CsvCache(study), json.loads((study / "figures.json").read_text())["figures"]


def check_sensitivity(study: Path, python_dir: Path, **_) -> None:
    """6. The sensitivity plot: at most 3 shaper curves per panel, the legend off the curves."""
    figures, cache, specs = _figures(study, python_dir)
    spec = next((s for s in specs if s.get("kind") == "sensitivity"), None)
    if spec is None:
        print("no sensitivity figure")
        return
    fig = figures.draw(spec, cache)
    axes = [a for a in fig.axes if a.get_visible() and a.get_lines()]
    counts = [sum(1 for ln in a.get_lines() if len(ln.get_xdata()) > 2) for a in axes]
    print(f"{len(spec['series'])} series in {len(axes)} panels, curves per panel {counts}")
    expect(max(counts) <= 3, f"a panel holds {max(counts)} curves")
    expect(all(_legend_clear_of_data(fig, a) for a in fig.axes), "a legend sits on the curves")


def check_md_summary(study: Path, python_dir: Path, **_) -> None:
    """7. The summary chart: "without" bars in a colour no shaped bar has; legends off the bars."""
    sys.path.insert(0, str(python_dir))
    from matplotlib.colors import to_rgb  # noqa: E402
    from clearshape_plot import figures  # noqa: E402
    figures.use_style()
    rows = [{"table": "5.1", "label": f"5.1 {r.upper()}", "role": r, "ours_without": 0.45, "thesis_without": 0.39,
             "ours_with": w, "thesis_with": w + 0.05, "ours_improvement": 100 * (1 - w / 0.45),
             "thesis_improvement": 100 * (1 - (w + 0.05) / 0.39)}
            for r, w in (("zv", 0.17), ("zvd", 0.15), ("zvdd", 0.13), ("mzv", 0.16), ("ei", 0.15))]
    fig = figures.draw({"id": "md-summary", "kind": "md-summary", "unit": "deg_s", "title": "t", "rows": rows}, None)
    ax, ax2 = fig.axes[:2]
    lab = _lab
    by_label = {c.get_label(): list(c) for c in ax.containers}  # one table's unshaped pair is drawn once
    without = [to_rgb(p.get_facecolor()[:3]) for p in by_label["without shaping — clearshape"]]
    shaped = [to_rgb(p.get_facecolor()[:3]) for p in by_label["with shaping — clearshape"]]
    d = min(math.dist(lab(w), lab(s)) for w in without for s in shaped)
    print(f"smallest CIELAB ΔE between a 'without' and a shaped bar: {d:.1f}")
    expect(d >= 40, f"a shaped bar's colour is close to the 'without' colour (ΔE {d:.1f})")
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    for a in (ax, ax2):
        leg = a.get_legend()
        if leg is None:
            continue
        box = leg.get_window_extent(r)
        over = [p for p in a.patches if p.get_height() > 0 and box.overlaps(p.get_window_extent(r))]
        expect(not over, f"a legend covers {len(over)} bars")


def _lab(rgb):
    """sRGB (0–1) → CIELAB (D65)."""
    c = [((v + 0.055) / 1.055) ** 2.4 if v > 0.04045 else v / 12.92 for v in rgb]
    x = (0.4124 * c[0] + 0.3576 * c[1] + 0.1805 * c[2]) / 0.95047
    y = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
    z = (0.0193 * c[0] + 0.1192 * c[1] + 0.9505 * c[2]) / 1.08883
    f = [t ** (1 / 3) if t > 0.008856 else 7.787 * t + 16 / 116 for t in (x, y, z)]
    return (116 * f[1] - 16, 500 * (f[0] - f[1]), 200 * (f[1] - f[2]))


def check_repeatability(study: Path, results: dict, python_dir: Path, **_) -> None:
    """8. Repeatability figures show each run's deviation from the mean with its Eq. 4.1 error, the
    same E as the consistency table; no legend on the curves of any line figure."""
    figures, cache, specs = _figures(study, python_dir)
    cons = [s for s in specs if str(s.get("id", "")).startswith("consistency-")]
    table = next((t for t in results.get("tables", []) if t.get("kind") == "consistency"), None)
    expect(bool(cons) and table is not None, "no repeatability figure or consistency table")
    compared = 0
    for spec in cons:
        fig = figures.draw(spec, cache)
        expect(len(fig.axes) >= 2, f"{spec['id']}: no deviation panel")
        if len(fig.axes) < 2:
            continue
        labels = fig.axes[1].get_legend_handles_labels()[1]
        e = [float(m.group(1)) for m in (re.search(r"E = ([0-9.e+-]+)", lab) for lab in labels) if m]
        key = spec["id"].removeprefix("consistency-")
        col = next((c for c in table["columns"] if c.get("key") == key), None) if table else None
        if col is not None and e:
            expect(len(e) == len(col["ours"]), f"{spec['id']}: {len(e)} runs in the legend, {len(col['ours'])} in the table")
            for a, b in zip(e, col["ours"]):
                expect(abs(a - b) <= 0.006 * abs(b), f"{spec['id']}: E {a} in the figure, {b} in Table {table['id']}")
                compared += 1
        expect(all(_legend_clear_of_data(fig, a) for a in fig.axes), f"{spec['id']}: a legend sits on the curves")
        plt_close(fig)
    for spec in specs:
        if spec.get("kind", "time-series") in ("time-series",) and not str(spec.get("id")).startswith("consistency-"):
            fig = figures.draw(spec, cache)
            expect(all(_legend_clear_of_data(fig, a) for a in fig.axes), f"{spec['id']}: a legend sits on the curves")
            plt_close(fig)
    print(f"{len(cons)} repeatability figures, {compared} Eq. 4.1 errors compared with the table")


def check_failing_criterion(html: str, python_dir: Path, **_) -> None:
    """9. A failing comparison states its criterion as failed (>), a passing one as held (≤)."""
    sys.path.insert(0, str(python_dir))
    from clearshape_plot import tables  # noqa: E402
    v = tables.verdict(2.0, 1.0, 0.5, "s.d.")
    expect(not v["agrees"] and ">" in v["criterion"] and "≤" not in v["criterion"], f"failing: {v['criterion']}")
    v = tables.verdict(1.2, 1.0)
    expect(not v["agrees"] and ">" in v["criterion"] and "≤" not in v["criterion"], f"failing: {v['criterion']}")
    v = tables.verdict(1.05, 1.0)
    expect(v["agrees"] and "≤" in v["criterion"], f"passing: {v['criterion']}")
    diff = section(html, "differences")
    differ = diff.split("<h3>Where clearshape differs</h3>")[1].split("<h3>")[0] if "Where clearshape differs" in diff else ""
    crits = re.findall(r'<span class="crit">([^<]*)</span>', differ)
    print(f"{len(crits)} failing rows")
    for c in crits:
        expect("≤" not in c and "contains 0" not in c and (">" in c or "&gt;" in c or "no relative criterion" in c
                                                           or "excludes 0" in c), f"failing row reads: {c}")


def check_no_outside_references(html: str, repo: Path, **_) -> None:
    """10. Neither the report nor any file of the repository points to a design note or a reference
    file that is not in the repository (the upper-case design file, the reference folder)."""
    pat = re.compile("DESIGN" + r"\.md|\b" + "reference" + r"/[a-z_]+\.md|\b(?:clearance_sim|sysid|aesthetics_ecosystem)"
                     + r"\.md")
    expect(not pat.search(html), "the report cites a file outside the repository")
    try:
        files = subprocess.run(["git", "-C", str(repo), "ls-files"], capture_output=True, text=True,
                               check=True).stdout.split()
    except (OSError, subprocess.CalledProcessError):
        files = [str(p.relative_to(repo)) for p in repo.rglob("*") if p.is_file()
                 and not any(part.startswith(("build", ".")) for part in p.relative_to(repo).parts)]
    hits = []
    for f in files:
        p = repo / f
        if not p.is_file() or p.stat().st_size > 2_000_000:
            continue
        try:
            text = p.read_text(encoding="utf-8")
        except (UnicodeDecodeError, OSError):
            continue
        if pat.search(text):
            hits.append(f)
    print(f"{len(files)} files searched; outside references in {hits or 'none'}")
    expect(not hits, f"files citing a file outside the repository: {hits[:10]}")


def check_rig_kind(study: Path, results: dict, tmp: Path, **_) -> None:
    """11. A rig that is not the thesis's is neither called calibrated to the thesis nor scored
    against it; the thesis's own simulated rig is."""
    seen = {}
    for kind in ("simulated-config", "simulated-large-play", "simulated-thesis", "physical", "recorded"):
        r = copy.deepcopy(results)
        r["rig"] = {"kind": kind, "description": f"test rig ({kind})"}
        html = render_copy(study, r, tmp)
        scored = 'class="verdict ok"' in html or 'class="verdict diff"' in html
        calibrated = "calibrated to what the thesis measured" in html
        seen[kind] = (scored, calibrated)
        if kind in ("simulated-config", "simulated-large-play"):
            expect(not scored, f"{kind}: the report scores the study against the thesis")
            expect(not calibrated, f"{kind}: the report says the rig was calibrated to the thesis")
            expect("not scored" in html.lower(), f"{kind}: the report does not say it is not scored")
        elif kind == "simulated-thesis":
            expect(scored and calibrated, "the thesis rig is no longer scored or called calibrated")
        else:
            expect(not calibrated, f"{kind}: a measured rig is called calibrated to the thesis")
            expect("measurement" in html, f"{kind}: the report does not say its runs are measurements")
    print(f"(scored, called calibrated) per rig kind: {seen}")


# ----------------------------------------------------------------------------------------------
# Issue 22: a report that survives a sceptical reader.

WORSE = "worse than unshaped"


def _rig_trial_tables(results: dict) -> list[dict]:
    return [t for t in results.get("tables", []) if t.get("kind") == "mean-deviation" and t.get("row_labels")
            and str(t["row_labels"][0]) == "1" and not any(":" in c.get("key", "") for c in t.get("columns", []))]


def _table_html(html: str, tid: str) -> str:
    """Every part of the table with id `tid` in the page."""
    slug = re.sub(r"[^a-z0-9]+", "-", tid.lower()).strip("-")
    parts = re.findall(rf'<table[^>]*id="table-{re.escape(slug)}(?:-part\d+)?"[^>]*>.*?</table>', html, re.S)
    return "".join(parts)


def _cells_of_row(table_html: str, row_label: str) -> list[str]:
    rows = re.findall(r"<tr[^>]*>(.*?)</tr>", table_html, re.S)
    out = []
    for r in rows:
        head = re.search(r"<th[^>]*>(.*?)</th>", r, re.S)
        if head and re.sub(r"<[^>]+>", "", head.group(1)).strip() == row_label:
            out += re.findall(r"<td[^>]*>(.*?)</td>", r, re.S)
    return out


def _worse_copy(results: dict) -> dict:
    """results.json with the first shaped rig column made worse than unshaped (its MDs doubled over the
    unshaped mean), the B.6-like summary negative, and a simulated shaper above the unshaped in row 1."""
    r = copy.deepcopy(results)
    for t in _rig_trial_tables(r):
        base = next((c for c in t["columns"] if c.get("key") == "none"), None)
        shaped = next((c for c in t["columns"] if c.get("key") != "none"), None)
        if base and shaped:
            shaped["ours"] = [2 * base["ours_mean"] for _ in shaped["ours"]]
            shaped["ours_mean"] = 2 * base["ours_mean"]
            shaped["improvement_percent"] = -100.0
            shaped["improvement_ci95_percent"] = [-130.0, -70.0]
            shaped["improvement_significant"] = True
            break
    for t in r.get("tables", []):
        if t.get("kind") == "improvement":
            t["columns"][0]["ours"] = [-37.0] + t["columns"][0]["ours"][1:]
        if t.get("id", "").endswith("-simulation"):
            base = next((c for c in t["columns"] if c.get("key") == "none"), None)
            other = next((c for c in t["columns"] if c.get("key") != "none"), None)
            if base and other:
                other["ours"] = [2 * base["ours"][0]] + other["ours"][1:]
    return r


def check_worse_marked(study: Path, results: dict, html: str, python_dir: Path, tmp: Path, **_) -> None:
    """22.1: every result worse than unshaped is marked in tables.md, in the HTML tables and in the summary
    figure, whose improvement axis reaches below 0; shaper bars in the shaper's colour (EI pink)."""
    md = (study / "tables.md").read_text(encoding="utf-8") if (study / "tables.md").exists() else ""
    negatives = 0
    for t in _rig_trial_tables(results):
        for c in t["columns"]:
            v = c.get("improvement_percent")
            if isinstance(v, (int, float)) and v < 0:
                negatives += 1
                cells = _cells_of_row(_table_html(html, t["id"]), "improvement")
                expect(any(WORSE in x for x in cells), f"Table {t['id']} {c['key']}: {v:.1f} % not marked in the page")
                if md:
                    line = next((ln for ln in md.splitlines() if ln.startswith(f"- {c['label']}: improvement ours")
                                 and f"{v:.1f}" in ln), "")
                    expect(WORSE in line, f"tables.md: {c['label']} ({v:.1f} %) not marked: {line!r}")
    print(f"{negatives} negative improvements in this study")
    worse = _worse_copy(results)
    page = render_copy(study, worse, tmp)
    for t in _rig_trial_tables(worse):
        for c in t["columns"]:
            if c.get("improvement_percent", 0) and c["improvement_percent"] < 0:
                cells = _cells_of_row(_table_html(page, t["id"]), "improvement")
                expect(any(WORSE in x and 'class="worse"' in page for x in cells), f"forced negative in {t['id']} not marked")
    for t in worse.get("tables", []):
        if t.get("kind") == "improvement":
            first = _cells_of_row(_table_html(page, t["id"]), t["row_labels"][0])
            expect(bool(first) and WORSE in first[0], f"Table {t['id']}: a negative improvement row is not marked")
        if t.get("id", "").endswith("-simulation") and any(c.get("key") == "none" for c in t["columns"]):
            expect(WORSE in _table_html(page, t["id"]), f"Table {t['id']}: a shaped MD above unshaped is not marked")
    sys.path.insert(0, str(python_dir))
    from matplotlib.colors import to_hex  # noqa: E402
    from clearshape_plot import figures  # noqa: E402
    figures.use_style()
    rows = [{"table": f"B.{i}", "label": f"B.{i}", "role": "ei", "ours_without": 0.3, "thesis_without": None,
             "ours_with": w, "thesis_with": None, "ours_improvement": 100 * (1 - w / 0.3),
             "ours_improvement_ci95": [100 * (1 - w / 0.3) - 10, 100 * (1 - w / 0.3) + 10],
             "thesis_improvement": None} for i, w in ((1, 0.4), (2, 0.61), (3, 0.1))]
    fig = figures.draw({"id": "s", "kind": "md-summary", "unit": "deg", "title": "t", "rows": rows}, None)
    ax2 = fig.axes[1]
    low = min(r["ours_improvement_ci95"][0] for r in rows)
    print(f"improvement axis {ax2.get_ylim()}, lowest interval end {low:.1f}")
    expect(ax2.get_ylim()[0] <= low, "the improvement axis cuts off results worse than unshaped")
    texts = [t.get_text() for t in ax2.texts]
    expect(sum(WORSE.replace(" ", "") in x.replace("\n", "").replace(" ", "") for x in texts) == 2,
           f"negative bars not labelled worse than unshaped: {texts}")
    colour = to_hex(ax2.patches[0].get_facecolor())
    expect(colour.lower() == "#cc79a7", f"EI's bars are {colour}, not EI's pink")
    expect(any(c.get_children() for c in ax2.containers if hasattr(c, "errorbar") and c.errorbar),
           "no error bars (bootstrap intervals) on the improvement bars")
    plt_close(fig)


def check_missing_is_null(study: Path, results: dict, html: str, **_) -> None:
    """22.3: a number the thesis does not give is null in results.json and "—" in the page, never 0."""
    zeros = []
    for t in results.get("tables", []):
        for c in t.get("columns", []):
            th = c.get("thesis")
            if isinstance(th, list) and th and all(v in (0, 0.0, None) for v in th) and any(v == 0 for v in th):
                zeros.append(f"{t['id']}:{c.get('key')}")
    proto_cl = results.get("protocol", {}).get("clearance", {}).get("thesis", {})
    print(f"thesis columns of zeros: {zeros or 'none'}; protocol clearance thesis {proto_cl}")
    expect(not zeros, f"thesis columns that hold 0 for no value: {zeros}")
    for k, v in proto_cl.items():
        expect(v != 0, f"protocol clearance.thesis.{k} = 0 stands for a missing value")
    figs = json.loads((study / "figures.json").read_text(encoding="utf-8")).get("figures", [])
    bad = [f["title"] for f in figs if re.search(r"thesis 0\.0+\b", str(f.get("title", "")))]
    expect(not bad, f"a figure title reads 'thesis 0': {bad}")
    md = (study / "tables.md").read_text(encoding="utf-8") if (study / "tables.md").exists() else ""
    for t in results.get("tables", []):
        for c in t.get("columns", []):
            ours = c.get("ours")
            if isinstance(ours, list) and None in ours and md:
                expect("| — |" in md or "— |" in md, f"tables.md prints a null of {t['id']} as nothing")
    # tables.md: no column that holds nothing but dashes (a thesis column where the thesis gives nothing).
    dashes = []
    for block in re.split(r"\n(?=### )", md):
        lines = [ln for ln in block.splitlines() if ln.startswith("|")]
        if len(lines) < 3:
            continue
        head = [x.strip() for x in lines[0].strip("|").split("|")]
        rows = [[x.strip() for x in ln.strip("|").split("|")] for ln in lines[2:]]
        for j in range(1, len(head)):
            cells = [r[j] for r in rows if j < len(r) and not r[0].startswith(("**", "std", "improvement"))]
            if cells and all(x in ("—", "") for x in cells) and any(x == "—" for x in cells):
                dashes.append(f"{block.splitlines()[0][4:40]}: {head[j]}")
    print(f"tables.md columns of dashes: {dashes or 'none'}")
    expect(not dashes, f"tables.md prints columns of nothing but —: {dashes[:4]}")


def check_thesis_verbatim(study: Path, results: dict, html: str, **_) -> None:
    """22.5: thesis numbers as printed — the printed improvement (not one recomputed from the means), the
    trial columns' digits (0.270), and no recomputed value in a thesis column; a recomputation that
    differs is said to be one."""
    proto = results.get("protocol", {}).get("rig_tests", {}).get("tables", [])
    printed = {(t["id"], c["key"]): c["thesis_improvement"] for t in proto for c in t.get("columns", [])
               if c.get("thesis_improvement") is not None}
    print(f"printed improvements in the protocol: {printed}")
    head = html[:html.find('<section id="setup"')]
    for t in _rig_trial_tables(results):
        for c in t["columns"]:
            key = (t["id"], c["key"])
            if key in printed:
                p = printed[key]
                expect(c.get("thesis_improvement_percent") == p,
                       f"{key}: results.json thesis improvement {c.get('thesis_improvement_percent')} ≠ printed {p}")
                cells = _cells_of_row(_table_html(html, t["id"]), "improvement")
                expect(any(f"{p:g} %" in x for x in cells), f"{key}: the page does not quote the printed {p:g} %")
                if f"Table {t['id']}" in head:
                    expect(f"thesis {p:g} %" in head, f"{key}: the header does not quote {p:g} %")
                rec = c.get("thesis_improvement_recomputed_percent")
                if isinstance(rec, (int, float)) and round(rec, 1) != p:
                    expect("recomputed" in _table_html(html, t["id"]), f"{key}: recomputed {rec:.2f} not noted")
            elif c.get("key") != "none":
                expect(c.get("thesis_improvement_percent") is None,
                       f"{key}: a thesis improvement the thesis never printed ({c.get('thesis_improvement_percent')})")
            th, tp = c.get("thesis") or [], c.get("thesis_printed") or []
            if th:
                expect(len(tp) == len(th), f"{key}: no thesis_printed digits")
                body = _table_html(html, t["id"])
                for text in tp:
                    expect(f'class="thesis">{text.replace("-", "−")}<' in body, f"{key}: thesis {text} not shown as printed")
                decimals = {len(x.split(".")[1]) for x in tp if x and "." in x and "×" not in x}
                expect(len(decimals) <= 1, f"{key}: one column printed with {decimals} decimals")
    for t in results.get("tables", []):
        if t.get("kind") == "parameters":
            for c in t.get("columns", []):
                for lab, v in zip(t.get("row_labels", []), c.get("thesis") or []):
                    expect(not ("=" in str(lab) and v is not None), f"{t['id']}: a recomputed '{lab}' = {v} "
                           "stands in the thesis column")


def check_rig_words(study: Path, results: dict, tmp: Path, **_) -> None:
    """22.2: each rig's report has its own words, from results.json rig (summary, calibrated_to_thesis,
    scored_against_thesis, documented): only the calibrated thesis rig is said to be calibrated to the
    thesis's unshaped means, has its flank called soft against the thesis's law and is compared with the
    thesis's shaped trials."""
    rig = results.get("rig", {})
    expect(isinstance(rig.get("summary"), str) and rig["summary"], "results.json rig has no summary")
    expect("calibrated_to_thesis" in rig and "scored_against_thesis" in rig, "results.json rig lacks its flags")
    phrases = ("calibrated to the thesis's <em>unshaped</em>", "agreement with the thesis's shaped trials",
               "calibrated to what the thesis measured")
    seen = {}
    for kind, summary, documented in (
            ("simulated-worn-coupling", "the worn test rig: 1° of play on a soft flank, a Coulomb torque.",
             {"contact_exponent": 1.0, "play_deg": 1.0}),
            ("simulated-large-play", "the large test rig: a 1° steel pin.", {"contact_exponent": 1.5, "play_deg": 1.0}),
            ("simulated-config", "a configured test rig.", None)):
        r = copy.deepcopy(results)
        r["rig"] = {"kind": kind, "description": "test", "summary": summary, "calibrated_to_thesis": False,
                    "scored_against_thesis": False}
        if documented:
            r["rig"]["documented"] = documented
        fit = r.get("sections", {}).get("clearance")
        if kind == "simulated-large-play" and isinstance(fit, dict) and isinstance(fit.get("exponent"), (int, float)):
            fit["exponent"] = 2.045  # the large-play study's fit: a nonlinear flank is never called linear
        page = render_copy(study, r, tmp)
        found = [p for p in phrases if p in page]
        seen[kind] = found
        expect(not found, f"{kind}: the thesis rig's words on another rig: {found}")
        expect(summary.rstrip(". ") in page, f"{kind}: the rig's own summary is not in the report")
        cl = section(page, "clearance")
        cl_res = r.get("sections", {}).get("clearance", {})
        n = cl_res.get("exponent")
        if documented and isinstance(n, (int, float)) and abs(n - documented["contact_exponent"]) > 0.1 \
                and "The fitted flank" in cl:
            expect("documented joint differs" in cl, f"{kind}: a fit that misses the documented n is not said to")
        if isinstance(n, (int, float)) and abs(n - 1.0) >= 0.1 and "The fitted flank" in cl:
            linear = [w for w in ("fitted linear flank", "nearly linear") if w in cl]
            expect(not linear, f"{kind}: a fitted flank with n = {n} called {linear}")
            expect(f"n = {n:.3g}" in cl, f"{kind}: the fitted n = {n:.3g} is not given where the flank is discussed")
    print(f"thesis-rig phrases found per rig: {seen}")


def check_finding(study: Path, results: dict, html: str, **_) -> None:
    """22.4/22.7/22.8: the header holds the finding — counts that include the not comparable ones and
    match the differences section, what is within noise (bootstrap intervals holding 0, marked "not
    significant" in the tables), verdicts on means against the standard error, not one trial's s.d."""
    head = html[:html.find('<section id="setup"')]
    expect('id="finding"' in head, "no finding in the header")
    m = re.search(r"(\d+) published numbers compared with the thesis: (\d+) agree, (\d+) differ, (\d+) not "
                  r"comparable", head)
    scored = results.get("rig", {}).get("scored_against_thesis", True)
    if scored:
        expect(m is not None, "the header's count omits the not comparable ones")
        d = section(html, "differences")
        m2 = re.search(r"(\d+) published numbers compared: <strong>(\d+) agree</strong>, <strong>(\d+) differ"
                       r"</strong>, (\d+) not comparable", d)
        expect(m is not None and m2 is not None and m.groups() == m2.groups(),
               f"header {m and m.groups()} and differences {m2 and m2.groups()} disagree")
        if m:
            expect(int(m.group(1)) == sum(int(x) for x in m.groups()[1:]), "the counts do not add up")
    ci_cols = 0
    for t in _rig_trial_tables(results):
        for c in t["columns"]:
            if c.get("key") == "none" or c.get("improvement_percent") is None:
                continue
            ci = c.get("improvement_ci95_percent")
            expect(isinstance(ci, list) and len(ci) == 2 and ci[0] <= ci[1],
                   f"{t['id']} {c['key']}: no bootstrap interval in results.json")
            if not isinstance(ci, list):
                continue
            ci_cols += 1
            cells = _cells_of_row(_table_html(html, t["id"]), "improvement")
            shown = f"[{ci[0]:.1f}, {ci[1]:.1f}]".replace("-", "−")
            expect(any(shown in x for x in cells), f"{t['id']} {c['key']}: interval {shown} not shown")
            expect(not any(re.search(r"(?<![\w.])-\d", re.sub(r"<[^>]+>", "", x)) for x in cells),
                   f"{t['id']}: a hyphen-minus among the improvement cells (the page uses −)")
            if ci[0] <= 0 <= ci[1]:
                expect(any("not significant" in x for x in cells), f"{t['id']} {c['key']}: not marked not significant")
                expect(f"{c['label']}" in head and "Within noise" in head, f"{t['id']} {c['key']}: not in the "
                       "header's 'within noise'")
    print(f"{ci_cols} shaped columns with bootstrap intervals")
    crits = re.findall(r'<span class="crit">([^<]*)</span>', section(html, "differences"))
    means = [c for c in crits if "trial-to-trial" in c]
    expect(not means, f"verdicts still judged within one thesis trial s.d.: {means[:2]}")


def check_figure_colours(study: Path, python_dir: Path, **_) -> None:
    """22.10: no two curves of a rig figure share a look (without IS and take-up both vermillion, MZV and
    clearance-aware both blue): every labelled line differs from the others in colour or line style."""
    figures, cache, specs = _figures(study, python_dir)
    from matplotlib.colors import to_hex  # noqa: E402
    clashes, drawn = [], 0
    for spec in specs:
        if not str(spec.get("id", "")).startswith("rig-") or spec.get("kind", "time-series") != "time-series":
            continue
        fig = figures.draw(spec, cache)
        drawn += 1
        for ax in fig.axes:
            looks = {}
            for ln in ax.get_lines():
                lab = ln.get_label()
                if lab.startswith("_") or len(ln.get_xdata()) < 3:
                    continue
                look = (to_hex(ln.get_color()), str(ln.get_linestyle()))
                if look in looks and looks[look] != lab:
                    clashes.append(f"{spec['id']}: {looks[look]!r} and {lab!r} both {look}")
                looks.setdefault(look, lab)
        plt_close(fig)
    print(f"{drawn} rig figures; clashes: {clashes[:4] or 'none'}")
    expect(not clashes, f"curves that look alike: {clashes[:4]}")


def check_zoom(study: Path, python_dir: Path, **_) -> None:
    """22.10: a rig trace is drawn where it rings, not over the whole record with the ringing in a few
    per cent of the width (an integrated gyro's slow drift does not hold the axis open): its time axis
    spans at most 75 % of the record (the whole record was drawn before) and holds every Eq. 5.1
    steady-state start it marks."""
    figures, cache, specs = _figures(study, python_dir)
    spans = []
    for spec in specs:
        if not re.match(r"rig-B\.|rig-5\.", str(spec.get("id", ""))) or spec.get("kind", "time-series") != "time-series":
            continue
        fig = figures.draw(spec, cache)
        x = cache.column(spec["file"], spec["x"]["column"])
        lo, hi = fig.axes[0].get_xlim()
        share = (hi - lo) / (float(x[-1]) - float(x[0]))
        spans.append(f"{spec['id']} {share:.0%}")
        expect(share <= 0.75, f"{spec['id']}: the axis spans {share:.0%} of the record")
        for key, a in (spec.get("mean_deviation") or {}).items():
            t0 = a.get("start_time_s")
            expect(t0 is None or lo <= t0 <= hi, f"{spec['id']}: the steady-state start of {key} is off the axis")
        plt_close(fig)
    print(f"rig traces, share of the record drawn: {spans or 'none'}")


def _band_share(ax) -> float:
    """The largest share of `ax`'s height that a ±MD band (an axhspan labelled "M ± MD") covers."""
    lo, hi = ax.get_ylim()
    share = 0.0
    for p in ax.patches:
        if not str(p.get_label()).lstrip("_").startswith("M ± MD"):
            continue
        ys = [v[1] for v in p.get_xy()] if hasattr(p, "get_xy") and not hasattr(p, "get_height") else \
            [p.get_y(), p.get_y() + p.get_height()]
        top, bottom = min(max(ys), max(lo, hi)), max(min(ys), min(lo, hi))
        share = max(share, max(0.0, top - bottom) / abs(hi - lo))
    return share


def check_md_band(study: Path, python_dir: Path, **_) -> None:
    """22.10: Eq. 5.1's ±MD band is visible in every mean-deviation figure: on the main axes or on a
    zoomed inset it covers at least 6 % of the height (a 0.39° band on a 25° step's axis covers 3 %)."""
    figures, cache, specs = _figures(study, python_dir)
    seen = []
    for spec in specs:
        if spec.get("kind") != "mean-deviation":
            continue
        fig = figures.draw(spec, cache)
        fig.canvas.draw()
        axes = [a for ax in fig.axes for a in [ax] + list(getattr(ax, "child_axes", []))]
        share = max((_band_share(a) for a in axes), default=0.0)
        seen.append(f"{spec['id']} {share:.1%}")
        expect(share >= 0.06, f"{spec['id']}: the ±MD band covers {share:.1%} of its axis at most")
        plt_close(fig)
    expect(bool(seen), "no mean-deviation figure")
    print(f"±MD band, largest share of an axis: {seen}")


def check_like_with_like(study: Path, results: dict, html: str, tmp: Path, **_) -> None:
    """22.8: verdicts compare like with like — the thesis's step model with ours from the same input (not
    our selected one), an exponent the fit could not identify is not scored, and clearshape's own tables
    are not named like the thesis's ("Table 4.3-clearance": the thesis has no Table 4.3)."""
    named = re.findall(r"<caption>Table ([^ <]+)", html)
    bad = [n for n in named if not re.fullmatch(r"(?:[0-9]+|B)\.[0-9]+", n)]
    print(f"tables captioned 'Table …': {named}")
    expect(not bad, f"clearshape tables named like the thesis's: {bad}")
    model = next((t for t in results.get("tables", []) if t.get("id") == "4.2-model"), None)
    thesis_col = next((c for c in (model or {}).get("columns", []) if c.get("key") == "thesis"), None)
    if thesis_col and thesis_col.get("input"):
        cap = re.search(r'id="table-4-2-model".*?<span class="unit">([^<]*)', html, re.S)
        print(f"4.2-model compared as: {cap and cap.group(1)}")
        ours = next(c for c in model["columns"] if c.get("key") == thesis_col["input"])
        expect(cap is not None and f"Δ = {ours['label']} −" in cap.group(1).replace("&#x27;", "'"),
               f"the thesis's {thesis_col['input']} model is not compared with ours from that input")
    else:
        expect(model is None or thesis_col is None, "the thesis's model column does not name its input")
    cl = results.get("sections", {}).get("clearance", {})
    if isinstance(cl, dict) and any(p.get("name") == "exponent" for p in cl.get("parameters") or []):
        r = copy.deepcopy(results)
        for p in r["sections"]["clearance"]["parameters"]:
            if p.get("name") == "exponent":
                p["identifiable"] = False
        page = render_copy(study, r, tmp)
        rows = re.findall(r'<th scope="row">exponent n</th>.*?<td class="verdict ([a-z ]+)"', page, re.S)
        print(f"an unidentified exponent's verdicts: {rows}")
        expect(rows and all(x == "na" for x in rows), f"an unidentifiable exponent is scored: {rows}")


def check_model_residual(study: Path, python_dir: Path, **_) -> None:
    """22.10: a model-vs-record overlay (identification, clearance fit, link-mode fit) has a residual
    panel below it, as MATLAB's compare: a second axes whose curve is record − model, recomputed here
    from the CSV columns, to 1e-9 of the record's span."""
    import numpy as np  # noqa: E402
    figures, cache, specs = _figures(study, python_dir)
    checked = []
    for spec in specs:
        panels = figures.panels_of(spec)
        if spec.get("kind", "time-series") != "time-series" or len(panels) != 1:
            continue
        series = panels[0].get("series") or []
        looks = {figures.roles.infer_role(s.get("column", ""), s.get("label"))[0] for s in series}
        if len(series) != 2 or looks != {"measured", "model"}:
            continue
        rec, mod = sorted(series, key=lambda s: figures.roles.infer_role(s["column"], s.get("label"))[0] != "measured")
        f = spec["file"]
        y, m = cache.column(f, rec["column"]), cache.column(f, mod["column"])
        want = y - m
        span = float(np.ptp(y)) or 1.0
        fig = figures.draw(spec, cache)
        axes = [a for a in fig.axes if a.get_visible() and a.axison]
        found = any(len(ln.get_ydata()) == len(want) and float(np.max(np.abs(np.asarray(ln.get_ydata()) - want)))
                    <= 1e-9 * span for a in axes[1:] for ln in a.get_lines())
        below = len(axes) > 1 and axes[1].get_position().y1 <= axes[0].get_position().y0 + 1e-6
        checked.append(f"{spec['id']} {'residual below' if found and below else 'NO residual panel'}")
        expect(found and below, f"{spec['id']}: no record − model panel under the overlay")
        plt_close(fig)
    print(f"model-vs-record figures: {checked or 'none'}")
    expect(bool(checked) or not any(str(s.get("id", "")).startswith("identification-") for s in specs),
           "identification figures are not recognised as model-vs-record overlays")


def check_delays(results: dict, html: str, python_dir: Path, **_) -> None:
    """22.11: a table's shaping delay is one the shaper can add — more than 0 and at most the shaper's
    duration (a ZVDD of 0.1 s delays a step's half-rise by under 0.1 s; a shaped PRBS or double step
    reaches half its final value on another step, which is no delay); the unshaped reference has no
    delay column (0 by definition); where a delay does not apply the cell reads "—"."""
    sys.path.insert(0, str(python_dir))
    from clearshape_plot import tables  # noqa: E402
    expect(not tables.delay_applies(0.0, 0.1) and not tables.delay_applies(0.424, 0.1)
           and tables.delay_applies(0.05, 0.1), "tables.delay_applies accepts a delay outside (0, duration]")
    shown = 0
    for t in results.get("tables", []):
        cols = [c for c in t.get("columns", []) if isinstance(c.get("delay_s"), list)]
        if not cols:
            continue
        page = next((x for x in tables_of(html) if x["id"] == f"table-{t['id'].lower().replace('.', '-')}"), None)
        expect(page is not None, f"table {t['id']} is not on the page")
        if page is None:
            continue
        head = [c[1] for c in page["rows"][0]]
        for c in cols:
            h = f"{c['label']}: delay s"
            unshaped = c.get("key") in ("none", "unshaped")
            expect(not (unshaped and h in head), f"{t['id']}: the unshaped reference has a delay column")
            if h not in head or unshaped:
                continue
            j, dur = head.index(h), c.get("shaper_duration_s")
            for r in page["rows"][1:]:
                cell = r[j][1] if j < len(r) else ""
                if cell in ("—", ""):
                    continue
                d = float(cell.replace("−", "-"))
                shown += 1
                expect(tables.delay_applies(d, dur), f"{t['id']} {r[0][1]}: {c['label']} delay {cell} s outside "
                       f"(0, {dur}] s")
    print(f"{shown} shaping delays shown, each within (0, the shaper's duration]")


def check_drift_apart(study: Path, html: str, python_dir: Path, **_) -> None:
    """22.10: a slow drift of the steady state (an integrated gyro's bias; 3/4 of a shaped MD² on the quick
    study) is reported apart from Eq. 5.1's MD: each mean-deviation figure draws the least-squares drift
    line of its steady state, recomputed here with numpy, and its caption says the drift is reported
    apart, not removed, with its share of MD²."""
    import numpy as np  # noqa: E402
    figures, cache, specs = _figures(study, python_dir)
    seen = []
    for spec in specs:
        if spec.get("kind") not in ("mean-deviation", "mean_deviation"):
            continue
        s = spec["series"][0]
        t, y = cache.column(spec["file"], spec["x"]["column"]), cache.column(spec["file"], s["column"])
        k = int(np.searchsorted(t, float(spec["start_time_s"])))
        slope = float(np.polyfit(t[k:] - t[k], y[k:], 1)[0])
        fig = figures.draw(spec, cache)
        lines = [ln for ln in fig.axes[0].get_lines() if "drift" in ln.get_label()]
        drawn = None
        if lines:
            x, v = np.asarray(lines[0].get_xdata(), float), np.asarray(lines[0].get_ydata(), float)
            drawn = (v[-1] - v[0]) / (x[-1] - x[0])
        expect(drawn is not None and abs(drawn - slope) <= 1e-6 * max(abs(slope), 1e-9) + 1e-12,
               f"{spec['id']}: no drift line of slope {slope:.3g} (drawn: {drawn})")
        fig_html = html[html.find(f'id="fig-{spec["id"]}"'):]
        cap = fig_html[fig_html.find("<figcaption>"):fig_html.find("</figcaption>")]
        m = re.search(r"Drift reported apart, not removed.*?\((\d+) % of MD² is the drift\)", cap)
        expect(m is not None, f"{spec['id']}: the caption does not report the drift apart")
        seen.append(f"{spec['id']}: slope {slope:.3g}/s, {m.group(1) if m else '?'} % of MD²")
        plt_close(fig)
    print(f"mean-deviation figures: {seen or 'none'}")


def check_legend_strip(study: Path, python_dir: Path, **_) -> None:
    """22.10: legends do not shrink the plots (rig figures' axes were 51 % of the figure's width, a
    legend beside them): in every single-column figure (all but the summary and sensitivity panels) each
    panel with data keeps at least 80 % of the figure's width, and no legend sits on the data."""
    figures, cache, specs = _figures(study, python_dir)
    widths = []
    for spec in specs:
        if spec.get("kind") in ("md-summary", "sensitivity"):  # side-by-side panels by design (own checks)
            continue
        fig = figures.draw(spec, cache)
        fig.canvas.draw()
        axes = [a for a in fig.axes if a.get_visible() and a.axison and a.get_lines()]
        if len(axes) > 3 or not axes:  # small multiples sit side by side by design
            plt_close(fig)
            continue
        w = min(a.get_position().width for a in axes)
        widths.append(w)
        expect(w >= 0.8, f"{spec['id']}: a panel keeps {w:.0%} of the figure's width")
        expect(all(_legend_clear_of_data(fig, a) for a in axes), f"{spec['id']}: a legend sits on the data")
        plt_close(fig)
    print(f"{len(widths)} figures; narrowest panel {min(widths, default=0):.0%} of the figure's width")


def _summary_specs(study: Path, results: dict, python_dir: Path):
    figures, cache, specs = _figures(study, python_dir)
    spread = getattr(figures, "with_trial_spreads", lambda s, _: s)  # a renderer without it draws none
    return figures, [spread(s, results) for s in specs if s.get("kind") == "md-summary"]


def check_summary_bars(study: Path, results: dict, python_dir: Path, **_) -> None:
    """22.10: the summary chart's mean-deviation bars carry ±1 s.d. over their trials (recomputed here from
    results.json's trial values), shaped bars a tenth of the unshaped ones stand on a log axis, and the
    title names each panel's unit instead of one "%" over degrees."""
    import numpy as np  # noqa: E402
    figures, specs = _summary_specs(study, results, python_dir)
    tables = {t["id"]: t for t in results.get("tables", [])}
    n_err = 0
    for spec in specs:
        fig = figures.draw(spec, None)
        ax = fig.axes[0]
        spans = sorted(round(float(abs(seg[1][1] - seg[0][1])), 9) for c in ax.collections for seg in c.get_segments())
        for r in spec["rows"]:
            for key, col in (("without", "none"), ("with", None)):
                t = tables.get(r["table"], {})
                vals = next((c["ours"] for c in t.get("columns", []) if c.get("ours") and
                             abs(np.mean(c["ours"]) - r[f"ours_{key}"]) <= 1e-9 * r[f"ours_{key}"]), None)
                if not vals or len(vals) < 2:
                    continue
                sd, v = float(np.std(vals, ddof=1)), r[f"ours_{key}"]
                want = round(min(sd, 0.9 * v) + sd, 9)
                expect(any(abs(x - want) <= 1e-6 * want for x in spans),
                       f"{spec['id']} {r['label']}: no ±1 s.d. error bar ({sd:.3g}) on the {key}-shaping bar")
                n_err += 1
        lows = [r["ours_with"] for r in spec["rows"] if r.get("ours_with")]
        highs = [r["ours_without"] for r in spec["rows"] if r.get("ours_without")]
        if lows and highs and min(lows) < max(highs) / 10:
            expect(ax.get_yscale() == "log", f"{spec['id']}: shaped bars on a linear axis")
        title = fig._suptitle.get_text() if fig._suptitle else ""
        unit = figures.roles.pretty_unit(spec.get("unit") or "")
        expect(unit in title and "%" in title, f"{spec['id']}: the title does not name both panels' units: {title!r}")
        plt_close(fig)
    print(f"{len(specs)} summary charts, {n_err} error bars compared with the trials' s.d.")
    expect(n_err > 0 or not specs, "no summary bar with trials to compare")


def check_tick_labels(study: Path, results: dict, python_dir: Path, **_) -> None:
    """22.10: no two tick labels of a figure overlap, and the summary chart of a table with several shapers
    (the speed study's 5.1 with ZV, ZVD, ZVDD) draws its unshaped pair once, names the shaped bars by the
    shaper, never "5.1 ZV"."""
    figures, cache, specs = _figures(study, python_dir)
    overlaps = []
    for spec in specs:
        fig = figures.draw(spec, cache)
        fig.canvas.draw()
        r = fig.canvas.get_renderer()
        for ax in fig.axes:
            if not ax.get_visible():
                continue
            for labels in (ax.get_xticklabels(), ax.get_yticklabels()):
                boxes = [(t.get_text(), t.get_window_extent(r)) for t in labels if t.get_text() and t.get_visible()]
                boxes = [(a, b) for a, b in boxes if ax.bbox.x0 - 2 <= (b.x0 + b.x1) / 2 <= ax.bbox.x1 + 2
                         or labels is ax.get_yticklabels()]
                for (ta, a), (tb, b) in zip(boxes, boxes[1:]):
                    if a.overlaps(b):
                        overlaps.append(f"{spec['id']}: {ta!r} / {tb!r}")
        plt_close(fig)
    rows = [{"table": "5.1", "label": f"5.1 {k.upper()}", "role": k, "ours_without": 0.6, "thesis_without": 0.39,
             "ours_with": w, "thesis_with": w + 0.03, "ours_improvement": 100 * (1 - w / 0.6), "thesis_improvement": None}
            for k, w in (("zv", 0.19), ("zvd", 0.16), ("zvdd", 0.14))]
    fig = figures.draw({"id": "speed", "kind": "md-summary", "unit": "deg_s", "title": "t", "rows": rows}, None)
    ax = fig.axes[0]
    without = [p for p in ax.patches if p.get_height() == 0.6]
    ticks = [t.get_text() for a in fig.axes[:2] for t in a.get_xticklabels()]
    print(f"overlapping tick labels: {overlaps[:4] or 'none'}; one table of 3 shapers: {len(without)} unshaped "
          f"bar(s), ticks {ticks}")
    expect(not overlaps, f"tick labels overlap: {overlaps[:4]}")
    expect(len(without) == 1, f"the unshaped bar of one table is drawn {len(without)} times")
    expect(not any(re.match(r"^\d+\.\d+ [A-Z]", t) for t in ticks), f"ticks read like '5.1 ZV': {ticks}")
    plt_close(fig)


def _number_format(cell: str):
    """("sci",) for a ×10ⁿ number, ("fixed", decimals) for a plain one, None for no number."""
    m = re.match(r"^[+−-]?(\d+)(?:\.(\d+))?(×10)?", cell.strip())
    if not m:
        return None
    return ("sci",) if m.group(3) else ("fixed", len(m.group(2) or ""))


def check_number_formats(html: str, **_) -> None:
    """22.11: one number format per column — in a trial table each clearshape column's trials and mean
    print with the same decimals or all as ×10ⁿ (0.38 stood above 0.3845) — and one minus sign: no table
    cell holds a hyphen-minus before a number or an "e-05" exponent."""
    mixed, hyphens, columns = [], [], 0
    for t in tables_of(html):
        for row in t["rows"]:
            for _, text, _ in row:
                if re.search(r"(?<![\w.])-\d|\de[-+]?\d", text):
                    hyphens.append(f"{t['id'] or t['class']}: {text[:50]!r}")
        if "trials" not in t["class"]:
            continue
        body = [r for r in t["rows"] if r and (r[0][1].isdigit() or r[0][1] == "mean")]
        width = max((len(r) for r in body), default=0)
        for j in range(1, width, 2):  # clearshape, thesis, clearshape, thesis, …
            looks = {_number_format(r[j][1]) for r in body if j < len(r) and r[j][1] not in ("", "—")} - {None}
            columns += 1
            if len(looks) > 1:
                mixed.append(f"{t['id']} column {(j + 1) // 2}: {sorted(looks)}")
    print(f"{columns} clearshape trial columns; mixed formats: {mixed[:3] or 'none'}; hyphen-minus or e-notation "
          f"cells: {hyphens[:3] or 'none'}")
    expect(not mixed, f"columns printed in more than one format: {mixed[:4]}")
    expect(not hyphens, f"cells with '-' or 'e-' in a number: {hyphens[:4]}")


def check_design_colours(study: Path, python_dir: Path, **_) -> None:
    """22.10: one colour per design across every figure (roles.py's fixed design → colour map): in no figure
    do two labelled curves share colour and line style, and a design's colour is drawn only for that design
    (two inputs of one figure were MZV blue and "without IS" vermillion)."""
    figures, cache, specs = _figures(study, python_dir)
    from matplotlib.colors import to_hex  # noqa: E402
    roles = figures.roles
    owner = {roles.ROLE_STYLES[r]["color"].lower(): r for r in roles.SHAPER_ORDER if r in roles.ROLE_STYLES}
    names = {r: {r, roles.SHAPER_LABELS.get(r, r).lower()} | ({"unshaped", "without"} if r == "unshaped" else set())
             for r in owner.values()}
    clashes, borrowed, curves = [], [], 0
    for spec in specs:
        fig = figures.draw(spec, cache)
        for ax in fig.axes:
            looks = {}
            leg = ax.get_legend()
            context = " ".join([ax.get_title("left"), ax.get_title(), leg.get_title().get_text() if leg else ""])
            for ln in ax.get_lines():
                lab = ln.get_label()
                if lab.startswith("_") or len(ln.get_xdata()) < 3:
                    continue
                curves += 1
                colour = to_hex(ln.get_color()).lower()
                look = (colour, str(ln.get_linestyle()))
                if look in looks and looks[look] != lab:
                    clashes.append(f"{spec['id']}: {looks[look]!r} and {lab!r}")
                looks.setdefault(look, lab)
                role = owner.get(colour)
                if role and not any(n in f"{lab} {context}".lower() for n in names[role]):
                    borrowed.append(f"{spec['id']}: {lab!r} in {role}'s colour")
        plt_close(fig)
    print(f"{len(specs)} figures, {curves} labelled curves; clashes {clashes[:3] or 'none'}; design colours on "
          f"other curves {borrowed[:3] or 'none'}")
    expect(not clashes, f"curves that look alike: {clashes[:4]}")
    expect(not borrowed, f"a design's colour on another curve: {borrowed[:4]}")


def check_zoom_note(study: Path, html: str, python_dir: Path, **_) -> None:
    """22.10: a time axis zoomed to the move says so: the figure's caption gives the drawn window (the axis's
    limits, to 0.01 s) and the whole record's span and file."""
    figures, cache, specs = _figures(study, python_dir)
    notes = 0
    for spec in specs:
        if spec.get("kind", "time-series") != "time-series" or spec.get("x", {}).get("column") != "time_s":
            continue
        fig = figures.draw(spec, cache)
        lo, hi = fig.axes[0].get_xlim()
        x = cache.column(spec["file"], "time_s")
        plt_close(fig)
        if hi - lo >= 0.9 * (float(x[-1]) - float(x[0])):
            continue
        at = html.find(f'href="figures/{spec["id"]}.pdf"')  # the figure's own caption links its files
        cap = html[html.rfind("<figcaption>", 0, at):at] if at >= 0 else ""
        want = f"{lo:.2f}–{hi:.2f} s of the {float(x[0]):.3g}–{float(x[-1]):.3g} s record"
        expect(want in cap and spec["file"] in cap, f"{spec['id']}: the caption does not say '{want}' ({spec['file']})")
        notes += 1
    print(f"{notes} zoomed time axes, each with its window and record in the caption")
    expect(notes > 0, "no zoomed time axis to check")


def _visible_text(html: str) -> str:
    """The page's prose, tables and captions: no embedded images, scripts, styles or <pre> dumps."""
    text = re.sub(r'src="data:[^"]*"', "", html)
    text = re.sub(r"<(pre|script|style)\b.*?</\1>", "", text, flags=re.S)
    return re.sub(r"<[^>]+>", " ", text)


def check_study_texts(study: Path, results: dict, html: str, **_) -> None:
    """22.10 (texts the C++ study writes): a summary figure's title names each quantity in its own unit
    (the improvement table's "…, %" title stood over the mean deviations' degrees), and no number of
    the page is in e-notation ("Coulomb 4.92e-05 N·m"): a unit with a prefix instead."""
    index = json.loads((study / "figures.json").read_text(encoding="utf-8")).get("figures", [])
    pct_titles = [t.get("title", "") for t in results.get("tables", []) if t.get("unit") == "%"]
    summaries = [f for f in index if f.get("kind") == "md-summary"]
    for f in summaries:
        title, unit = f.get("title", ""), f.get("unit", "")
        md = title.find(f"mean deviation ({unit})")
        expect(md >= 0, f"{f['id']}: the title does not give the mean deviation's unit ({unit}): {title!r}")
        expect("%" not in title[:max(md, 0)], f"{f['id']}: a % before the mean deviation in {title!r}")
        expect(not any(t and t in title for t in pct_titles), f"{f['id']}: a % table's title over {unit}: {title!r}")
    text = _visible_text(html)
    enotation = [text[max(0, m.start() - 40):m.end() + 10] for m in re.finditer(r"(?<![\w.])\d+(?:\.\d+)?[eE][-+−]?\d+(?!\w)", text)]
    expect(not enotation, f"numbers in e-notation: {enotation[:3]}")
    coulomb = re.findall(r"Coulomb (\S+) (\S+) ±", text)
    for value, unit in coulomb:
        expect(unit in ("N·m", "mN·m", "µN·m") and re.fullmatch(r"[0-9.]+", value) is not None,
               f"a Coulomb torque printed as {value} {unit}")
    print(f"{len(summaries)} summary titles, {len(coulomb)} dropped Coulomb torques, {len(enotation)} e-notation numbers")


def _bootstrap_means(x, rng):
    """Every equally likely resample mean of `x` (exact when n^n ≤ 10⁵), else 10⁵ random ones."""
    import itertools
    import numpy as np
    if len(x) ** len(x) <= 100_000:
        return np.array([np.mean(p) for p in itertools.product(x, repeat=len(x))]), True
    return rng.choice(np.asarray(x), size=(100_000, len(x))).mean(axis=1), False


def check_bootstrap_reference(results: dict, **_) -> None:
    """22.4: each shaped column's 95 % interval of the improvement is the percentile bootstrap over the
    trials (each group resampled on its own; Efron & Tibshirani 1993, §13.3), recomputed independently
    with NumPy — exactly, over every resample, for the quick study's 3 trials — to 5 % of its width,
    and "significant" exactly when the interval excludes 0."""
    import numpy as np
    rng = np.random.default_rng(22)
    compared, worst = 0, 0.0
    for t in _rig_trial_tables(results):
        base = next((c for c in t["columns"] if c.get("key") == "none"), None)
        for c in t["columns"]:
            ci = c.get("improvement_ci95_percent")
            if c is base or base is None or not isinstance(ci, list) or not all(isinstance(v, (int, float)) for v in ci):
                continue
            mu, exact_u = _bootstrap_means(base["ours"], rng)
            mw, exact_w = _bootstrap_means(c["ours"], rng)
            exact = exact_u and exact_w  # else both random: independent resamples, paired at random
            stat = (100.0 * (1.0 - mw[None, :] / mu[:, None])).ravel() if exact else \
                100.0 * (1.0 - rng.permutation(mw)[:min(len(mu), len(mw))] / mu[:min(len(mu), len(mw))])
            lo, hi = np.percentile(stat, [2.5, 97.5])
            off = max(abs(ci[0] - lo), abs(ci[1] - hi)) / max(hi - lo, 1e-9)
            worst = max(worst, off)
            compared += 1
            # The study's 4000 resamples put a quantile within ~1 % of the width (1σ); a 90 % interval
            # would be ~8 % off: 5 % against the exact reference, 8 % against a random one.
            expect(off <= (0.05 if exact else 0.08),
                   f"{t['id']} {c['key']}: interval {ci} against the reference [{lo:.3f}, {hi:.3f}]")
            sig = c.get("improvement_significant")
            expect(sig == (not ci[0] <= 0 <= ci[1]), f"{t['id']} {c['key']}: significant = {sig} for {ci}")
    expect(compared > 0, "no bootstrap interval to compare")
    print(f"{compared} intervals against the NumPy reference; worst endpoint off by {100 * worst:.1f} % of the width")


def check_print_reader(python_dir: Path, **_) -> None:
    """22.12. report_print.py's reading of a printed page, on blocks placed by hand (points from the
    page's top; column 40–740 pt): a heading at a page's foot with its text on the next page, an
    explanation row apart from its number row, a page 30 % full before a tall figure and a figure on
    two pages are each found; the same blocks laid out well give nothing."""
    sys.path.insert(0, str(python_dir))
    import report_print as rp  # noqa: E402

    def mark(page, top, bottom, index, tag, cls="-", text="x"):
        return {"page": page, "top": top, "bottom": bottom, "index": index, "tag": tag, "class": cls.split("."),
                "text": text}
    good = [mark(0, 40, 60, 0, "h2"), mark(0, 60, 600, 1, "p"), mark(0, 600, 620, 2, "tr", "nums"),
            mark(0, 620, 640, 3, "tr", "reason"), mark(1, 40, 300, 4, "figure"), mark(1, 300, 740, 5, "p")]
    bad = [mark(0, 40, 60, 0, "h2"), mark(0, 60, 230, 1, "p"), mark(0, 230, 250, 2, "tr", "nums"),
           mark(1, 40, 60, 3, "tr", "reason"), mark(1, 60, 700, 4, "p"), mark(1, 700, 720, 5, "h3"),
           mark(2, 40, 600, 6, "figure"), mark(3, 40, 200, 6, "figure"), mark(3, 200, 740, 7, "p")]
    ok, found = rp.analyse(2, good), rp.analyse(4, bad)
    print("laid out well:", {k: ok[k] for k in ("stranded", "split_reasons", "half_empty", "split_figures")})
    print("laid out badly:", {k: found[k] for k in ("stranded", "split_reasons", "half_empty", "split_figures")})
    for key in ("stranded", "split_reasons", "half_empty", "split_figures"):
        expect(not ok[key], f"{key} found in a good layout: {ok[key]}")
        expect(len(found[key]) == 1, f"{key}: expected one, found {found[key]}")
    expect(found["fills"][0] == 0.3, f"page 1 filled {found['fills'][0]}, not 0.3")


CHECKS = {
    "print-reader": check_print_reader, "md-band": check_md_band,
    "link-mode-fit": check_link_mode_fit, "clearance-identified": check_clearance_identified,
    "empty-columns": check_empty_columns, "layout-1400": check_layout_1400, "is-spelling": check_is_spelling,
    "sensitivity": check_sensitivity, "md-summary": check_md_summary, "repeatability": check_repeatability,
    "failing-criterion": check_failing_criterion, "outside-references": check_no_outside_references,
    "rig-kind": check_rig_kind, "worse-marked": check_worse_marked, "missing-null": check_missing_is_null,
    "thesis-verbatim": check_thesis_verbatim, "rig-words": check_rig_words, "finding": check_finding,
    "figure-colours": check_figure_colours, "zoom": check_zoom, "like-with-like": check_like_with_like,
    "model-residual": check_model_residual, "delays": check_delays,
    "drift-apart": check_drift_apart, "legend-strip": check_legend_strip,
    "summary-bars": check_summary_bars, "tick-labels": check_tick_labels,
    "number-formats": check_number_formats, "design-colours": check_design_colours,
    "zoom-note": check_zoom_note, "study-texts": check_study_texts,
    "bootstrap-reference": check_bootstrap_reference,
}


def main(argv) -> int:
    if len(argv) < 3 or argv[0] not in CHECKS:
        print(f"usage: report_checks.py <{'|'.join(CHECKS)}> <study-dir> <python-dir> [<repo-root>]", file=sys.stderr)
        return 2
    study, python_dir = Path(argv[1]), Path(argv[2])
    repo = Path(argv[3]) if len(argv) > 3 else python_dir.parent
    sys.path.insert(0, str(python_dir))
    results = json.loads((study / "results.json").read_text(encoding="utf-8"))
    html = (study / "report.html").read_text(encoding="utf-8")
    with tempfile.TemporaryDirectory(prefix="clearshape_checks_") as tmp:
        CHECKS[argv[0]](study=study, results=results, html=html, python_dir=python_dir, repo=repo, tmp=Path(tmp))
    for f in FAILURES:
        print(f"FAIL: {f}")
    return 1 if FAILURES else 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
