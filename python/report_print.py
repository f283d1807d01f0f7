#!/usr/bin/python3
"""Prints a study report to PDF in headless Chromium on Letter or A4 paper and reads back where each
block landed, so the print layout can be checked as the reader gets it.

    /usr/bin/python3 python/report_print.py <report.html> <dir> [--paper letter|a4]

Writes <dir>/print-<paper>.pdf and <dir>/print-<paper>.json:
  pages          pages printed
  stranded       headings (h1–h3, table captions) whose next block starts on a later page
  split_reasons  a compared number's explanation row (tr.reason) on another page than its number row
  half_empty     pages, except the last, filled less than HALF_EMPTY of their height, with the first
                 block of the next page (a block too tall to fit pushed there)
  split_figures  figures printed across two pages
  fills          each page's filled fraction
How: a temporary copy of the page gets an @page size and, on every block, an invisible link
(position:absolute, 3 px wide, the block's height) whose URL names the block. Chromium prints a link
as a PDF /Link annotation with the rectangle it occupies on its page, one per page it spans; the
annotations give each block's page and vertical extent. The report itself is never modified.
Exit codes: 0 written, 1 Chromium failed, 2 bad input.
"""
from __future__ import annotations

import json
import re
import sys
import tempfile
from pathlib import Path
from urllib.parse import unquote

from report_shots import chromium

PAPERS = {"letter": "letter", "a4": "A4"}
HALF_EMPTY = 0.5
BLOCKS = ("header > h1, header > p, header div.summary, header li, main h2, main h3, main p, main figure, "
          "main tr, main caption, main dl, main pre, main li, main div.warn, main div.summary")
URL = "https://block.invalid/"

# Marks every block with a link naming its index, tag and classes (document order).
MARK = """<script>window.addEventListener('load', function () {
  document.querySelectorAll('%s').forEach(function (e, i) {
    var a = document.createElement('a'), host = e.tagName === 'TR' ? e.firstElementChild : e;
    if (!host) return;
    var words = encodeURIComponent(e.textContent.trim().replace(/\\s+/g, ' ').slice(0, 40)).replace(/[()']/g, '_');
    a.href = '%s' + i + '/' + e.tagName.toLowerCase() + '/' + (e.className || '-').toString().replace(/\\s+/g, '.') +
             '/' + words;
    a.style.cssText = 'position:absolute;left:0;top:0;width:3px;height:100%%;display:block';
    a.setAttribute('aria-hidden', 'true');
    if (getComputedStyle(host).position === 'static') host.style.position = 'relative';
    host.appendChild(a);
  });
});</script>""" % (BLOCKS, URL)


def marked_copy(html: str, paper: str) -> str:
    style = f"<style>@page{{size:{PAPERS[paper]}}}</style>"
    return html.replace("</head>", style + "</head>", 1).replace("</body>", MARK + "</body>", 1)


def print_pdf(page: Path, pdf: Path, profile: Path) -> None:
    r = chromium(["--no-pdf-header-footer", f"--print-to-pdf={pdf}", f"file://{page}"], profile)
    if not pdf.exists():
        raise RuntimeError(f"chromium did not print {page}: {r.stderr[-300:]}")


def pdf_objects(pdf: bytes) -> dict[int, bytes]:
    # Chromium (Skia) writes plain indirect objects, no object streams.
    return {int(m.group(1)): m.group(2) for m in re.finditer(rb"(?s)(\d+) 0 obj\n(.*?)\nendobj", pdf)}


def page_leaves(objs: dict[int, bytes], node: int) -> list[int]:
    o = objs[node]
    if b"/Type /Pages" not in o:
        return [node]
    kids = re.search(rb"(?s)/Kids \[(.*?)\]", o).group(1)
    return [leaf for k in re.findall(rb"(\d+) 0 R", kids) for leaf in page_leaves(objs, int(k))]


def block_marks(pdf: bytes) -> tuple[int, list[dict]]:
    """Pages printed, and every block's fragment: page, top and bottom (points from the page's top)."""
    objs = pdf_objects(pdf)
    catalog = next(o for o in objs.values() if b"/Type /Catalog" in o)
    pages = page_leaves(objs, int(re.search(rb"/Pages (\d+) 0 R", catalog).group(1)))
    marks = []
    for number, ref in enumerate(pages):
        page = objs[ref]
        height = float(re.search(rb"/MediaBox \[([^\]]*)\]", page).group(1).split()[3])
        annots = re.search(rb"/Annots \[([^\]]*)\]", page)
        for a in re.findall(rb"(\d+) 0 R", annots.group(1)) if annots else []:
            uri = re.search(rb"/URI \((" + re.escape(URL.encode()) + rb"[^)]*)\)", objs[int(a)])
            if not uri:
                continue
            x0, y0, x1, y1 = (float(v) for v in re.search(rb"/Rect \[([^\]]*)\]", objs[int(a)]).group(1).split())
            index, tag, cls, words = uri.group(1).decode()[len(URL):].split("/", 3)
            marks.append({"page": number, "top": height - y1, "bottom": height - y0, "index": int(index),
                          "tag": tag, "class": cls.split("."), "text": unquote(words)})
    return len(pages), marks


def label(m: dict) -> str:
    cls = "".join("." + c for c in m["class"] if c != "-")
    return f"{m['tag']}{cls} “{m['text']}”"


def stranded(blocks: dict[int, list[dict]]) -> list[str]:
    """Headings whose next block (in document order, not one of their own parts) starts on a later page."""
    order = sorted(blocks)
    out = []
    for i, idx in enumerate(order):
        head = blocks[idx]
        if head[0]["tag"] not in ("h1", "h2", "h3", "caption") or i + 1 == len(order):
            continue
        nxt = blocks[order[i + 1]]
        if min(f["page"] for f in nxt) > max(f["page"] for f in head):
            out.append(f"{label(head[0])} on page {max(f['page'] for f in head) + 1}, then {label(nxt[0])}")
    return out


def split_reasons(blocks: dict[int, list[dict]]) -> list[str]:
    order = sorted(blocks)
    out = []
    for i, idx in enumerate(order[1:], start=1):
        row, prev = blocks[idx], blocks[order[i - 1]]
        if "reason" in row[0]["class"] and row[0]["tag"] == "tr" and "nums" in prev[0]["class"]:
            if min(f["page"] for f in row) != max(f["page"] for f in prev):
                out.append(f"{label(row[0])} on page {row[0]['page'] + 1}, "
                           f"its number row on page {prev[-1]['page'] + 1}")
    return out


def fills(pages: int, marks: list[dict]) -> list[float]:
    """Each page's filled fraction: from the column's top to its lowest block, over the column's height."""
    top = min(m["top"] for m in marks)
    bottom = max(m["bottom"] for m in marks)
    lowest = [max((m["bottom"] for m in marks if m["page"] == p), default=top) for p in range(pages)]
    return [round((b - top) / (bottom - top), 3) for b in lowest]


def analyse(pages: int, marks: list[dict]) -> dict:
    blocks: dict[int, list[dict]] = {}
    for m in marks:
        blocks.setdefault(m["index"], []).append(m)
    fill = fills(pages, marks)
    half = []
    for p in range(pages - 1):
        if fill[p] < HALF_EMPTY:
            first = min((m for m in marks if m["page"] == p + 1), key=lambda m: (m["top"], m["index"]), default=None)
            half.append(f"page {p + 1} filled {fill[p]:.0%}, next page starts with {label(first) if first else '—'}")
    figures = [label(b[0]) for b in blocks.values() if b[0]["tag"] == "figure" and len({f["page"] for f in b}) > 1]
    return {"pages": pages, "blocks": len(blocks), "stranded": stranded(blocks), "split_reasons": split_reasons(blocks),
            "half_empty": half, "split_figures": figures, "fills": fill}


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    paper = "letter"
    if "--paper" in argv:
        i = argv.index("--paper")
        paper = argv[i + 1] if i + 1 < len(argv) else ""
        argv = argv[:i] + argv[i + 2:]
    if len(argv) != 2 or not Path(argv[0]).is_file() or paper not in PAPERS:
        print("usage: report_print.py <report.html> <dir> [--paper letter|a4]", file=sys.stderr)
        return 2
    report, out = Path(argv[0]).resolve(), Path(argv[1])
    out.mkdir(parents=True, exist_ok=True)
    pdf = out / f"print-{paper}.pdf"
    pdf.unlink(missing_ok=True)
    with tempfile.TemporaryDirectory(prefix="clearshape_print_") as tmp:
        page = Path(tmp) / "page.html"
        page.write_text(marked_copy(report.read_text(encoding="utf-8"), paper), encoding="utf-8")
        try:
            print_pdf(page, pdf, Path(tmp) / "profile")
        except RuntimeError as e:
            print(f"report_print: {e}", file=sys.stderr)
            return 1
    pages, marks = block_marks(pdf.read_bytes())
    if not marks:
        print(f"report_print: no block found in {pdf}", file=sys.stderr)
        return 1
    result = {"paper": paper, **analyse(pages, marks)}
    (out / f"print-{paper}.json").write_text(json.dumps(result, indent=1, ensure_ascii=False) + "\n", encoding="utf-8")
    print(out / f"print-{paper}.json")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
