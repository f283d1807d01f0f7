#!/usr/bin/python3
"""Numbers the docs quote from a study's output are that output (issue 22, item 13).

A quote is marked in README.md or docs/*.md by an HTML comment (invisible on the rendered page):

    <!-- doc-numbers STUDY PATH:FORMAT [PATH:FORMAT ...] [stride=N] -->

STUDY names the study folder `make run` writes (out/STUDY/results.json). PATH is a key path into
that results.json: dot-separated keys, `name[key=value]` picks the element of a list whose `key` is
`value`, `name[i]` the i-th element, `name[k]` on an object its key k (one with dots: `[B.1]`); it
ends on a number or a list of numbers. FORMAT is a Python
format spec (`.1f`, `.4f`, `.0f`; `.2%` writes a fraction in per cent). The quoted text is the
marker's line when it holds more than markers (a table row ending in one), else the next line that
is not a marker (a whole code block when that line opens one). The formatted values of every PATH, in order, must be a run of
the numbers written in the quoted text (every `stride`-th one when stride is given: `94.4 / 96.3 %`
cells quote two numbers each). A value that changed, a key that is gone, a marker that quotes
nothing fail, naming the doc's file and line:

    /usr/bin/python3 scripts/check-doc-numbers.py [--out out] [--results STUDY=FILE ...]
                     [--only STUDY ...] [--docs FILE ...] [--repo DIR] [--require-all] [--lint]

Markers whose study has no results.json (not run) are reported as not checked, and fail only
with --require-all. Exit 0 when every checked quote holds, 1 when one drifted, 2 on a bad marker
or bad usage.
"""
from __future__ import annotations

import argparse
import json
import re
import sys
from pathlib import Path

MARKER = re.compile(r"<!--\s*doc-numbers\s+(.*?)\s*-->")
# A written number: not part of a word or of a dotted name ("B.6", "r01"); U+2212 or "-" as minus.
NUMBER = re.compile(r"(?<![\w.])[−-]?\d+(?:\.\d+)?(?![\w])")
SEGMENT = re.compile(r"^([^\[\]]+)((?:\[[^\]]+\])*)$")


class MarkerError(Exception):
    pass


def resolve(doc: dict, path: str):
    """The value at `path` (see the module's docstring) in the parsed results.json `doc`."""
    node = doc
    for seg in re.findall(r"(?:[^.\[]|\[[^\]]*\])+", path):  # dots inside [...] are the value's
        m = SEGMENT.match(seg)
        if not m:
            raise MarkerError(f"bad path segment '{seg}'")
        if not isinstance(node, dict) or m.group(1) not in node:
            raise MarkerError(f"no key '{m.group(1)}'")
        node = node[m.group(1)]
        for sel in re.findall(r"\[([^\]]+)\]", m.group(2)):
            if isinstance(node, dict):  # [key] on an object: a key with dots in it ("B.1")
                if sel not in node:
                    raise MarkerError(f"no key '{sel}' in '{m.group(1)}'")
                node = node[sel]
                continue
            if not isinstance(node, list):
                raise MarkerError(f"'{seg}' selects [{sel}] from a non-list")
            if "=" in sel:
                key, value = sel.split("=", 1)
                hits = [x for x in node if isinstance(x, dict) and str(x.get(key)) == value]
                if len(hits) != 1:
                    raise MarkerError(f"[{sel}] matches {len(hits)} elements of '{m.group(1)}'")
                node = hits[0]
            elif re.fullmatch(r"\d+", sel) and int(sel) < len(node):
                node = node[int(sel)]
            else:
                raise MarkerError(f"bad or out-of-range index [{sel}]")
    return node


def formatted(value, spec: str, path: str) -> list[str]:
    values = value if isinstance(value, list) else [value]
    if not values or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values):
        raise MarkerError(f"'{path}' is not a number or a list of numbers: {json.dumps(value)[:80]}")
    out = [format(float(v), spec).rstrip("%") for v in values]
    return [s.replace("-", "−") if s.startswith("-") else s for s in out]


def written_numbers(text: str) -> list[str]:
    return [n.replace("-", "−") for n in NUMBER.findall(text)]


def holds(expected: list[str], written: list[str], stride: int) -> bool:
    """`expected` is a run of `written` (every stride-th element from some start). −0.0 reads 0.0."""
    norm = [w.lstrip("−") if re.fullmatch(r"−0(\.0+)?", w) else w for w in written]
    exp = [e.lstrip("−") if re.fullmatch(r"−0(\.0+)?", e) else e for e in expected]
    span = (len(exp) - 1) * stride
    return any(norm[s:s + span + 1:stride] == exp for s in range(len(norm) - span))


def parse_marker(body: str):
    words = body.split()
    if len(words) < 2:
        raise MarkerError("expected: doc-numbers STUDY PATH:FORMAT [PATH:FORMAT ...] [stride=N]")
    study, stride, quotes = words[0], 1, []
    for w in words[1:]:
        if w.startswith("stride="):
            if not re.fullmatch(r"stride=[1-9]\d*", w):
                raise MarkerError(f"bad '{w}' (stride=N, N ≥ 1)")
            stride = int(w[7:])
        elif ":" in w:
            path, spec = w.rsplit(":", 1)
            try:
                format(1.0, spec)
            except ValueError as e:
                raise MarkerError(f"bad format '{spec}' ({e})") from None
            quotes.append((path, spec))
        else:
            raise MarkerError(f"'{w}' is not PATH:FORMAT or stride=N")
    if not quotes:
        raise MarkerError("no PATH:FORMAT")
    return study, quotes, stride


def markers(doc: Path):
    """(line number, marker body, quoted text) of every marker in `doc`."""
    lines = doc.read_text(encoding="utf-8").splitlines()
    for i, line in enumerate(lines):
        for m in MARKER.finditer(line):
            rest = MARKER.sub("", line).strip()
            j = i + 1
            while not rest and j < len(lines):
                candidate = lines[j].strip()
                if candidate.startswith("```"):  # a code block: all of it
                    end = next((k for k in range(j + 1, len(lines)) if lines[k].strip().startswith("```")), len(lines))
                    rest = "\n".join(lines[j + 1:end]) or " "
                elif candidate and not MARKER.fullmatch(candidate):
                    rest = MARKER.sub("", candidate)
                j += 1
            yield i + 1, m.group(1), rest


def lint(docs: list[Path], repo: Path) -> int:
    """Every marker parses and quotes a text with numbers in it (no results.json needed)."""
    n, bad = 0, 0
    for doc in docs:
        rel = doc.relative_to(repo) if doc.is_relative_to(repo) else doc
        for line, body, text in markers(doc):
            n += 1
            try:
                parse_marker(body)
                if not written_numbers(text):
                    raise MarkerError("the quoted text holds no number")
            except MarkerError as e:
                print(f"doc-numbers: {rel}:{line}: bad marker: {e}")
                bad += 1
    print(f"doc-numbers: {n} markers, {bad} bad")
    return 2 if bad else 0


def check(docs: list[Path], repo: Path, results: dict[str, Path], only: set[str], require_all: bool) -> int:
    cache: dict[str, dict] = {}
    bad, drifted, checked, unchecked = 0, 0, 0, set()
    for doc in docs:
        rel = doc.relative_to(repo) if doc.is_relative_to(repo) else doc
        for line, body, text in markers(doc):
            where = f"{rel}:{line}"
            try:
                study, quotes, stride = parse_marker(body)
                if only and study not in only:
                    continue
                file = results.get(study)
                if file is None or not file.exists():
                    unchecked.add(study)
                    continue
                if study not in cache:
                    cache[study] = json.loads(file.read_text(encoding="utf-8"))
                expected = [s for path, spec in quotes for s in formatted(resolve(cache[study], path), spec, path)]
            except MarkerError as e:
                print(f"doc-numbers: {where}: bad marker: {e}")
                bad += 1
                continue
            written = written_numbers(text)
            checked += 1
            if not holds(expected, written, stride):
                drifted += 1
                print(f"doc-numbers: {where}: the doc quotes {' '.join(written) or 'no number'}; "
                      f"{results[study]} gives {' '.join(expected)} ({', '.join(p for p, _ in quotes)})")
    missing = sorted(unchecked)
    if missing:
        print(f"doc-numbers: not checked (no results.json): {', '.join(missing)}")
    print(f"doc-numbers: {checked} quotes checked, {drifted} drifted, {bad} bad markers")
    if bad:
        return 2
    return 1 if drifted or (require_all and missing) else 0


def main(argv) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repo", type=Path, default=Path(__file__).resolve().parent.parent)
    ap.add_argument("--out", type=Path, default=None, help="folder of the study outputs (default REPO/out)")
    ap.add_argument("--results", action="append", default=[], metavar="STUDY=FILE",
                    help="the results.json of STUDY (overrides --out)")
    ap.add_argument("--only", action="append", default=[], metavar="STUDY", help="check this study's quotes only")
    ap.add_argument("--docs", action="append", type=Path, default=[], help="docs to read (default README.md, docs/*.md)")
    ap.add_argument("--require-all", action="store_true", help="fail when a marked study has no results.json")
    ap.add_argument("--lint", action="store_true", help="only parse the markers (no results.json read)")
    a = ap.parse_args(argv)
    repo = a.repo.resolve()
    out = (a.out or repo / "out").resolve()
    docs = [d.resolve() for d in a.docs] or [repo / "README.md", *sorted((repo / "docs").glob("*.md"))]
    results: dict[str, Path] = {}
    for d in docs:
        if not d.exists():
            print(f"doc-numbers: --docs {d}: no such file", file=sys.stderr)
            return 2
        for _, body, _ in markers(d):
            study = body.split()[0] if body.split() else ""
            results.setdefault(study, out / study / "results.json")
    if a.lint:
        return lint(docs, repo)
    for r in a.results:
        if "=" not in r:
            print(f"doc-numbers: --results {r}: expected STUDY=FILE", file=sys.stderr)
            return 2
        study, file = r.split("=", 1)
        results[study] = Path(file)
    return check(docs, repo, results, set(a.only), a.require_all)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
