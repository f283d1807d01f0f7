#!/usr/bin/env python3
"""Print one fenced code block of a Markdown file: the Nth (default first) ```LANG block under the
heading HEADING (a line `# HEADING` to `### HEADING`, up to the next heading), so
scripts/test-clean-root.sh runs the docs' own commands and fails when the docs drift.
usage: doc-block.py FILE.md HEADING LANG [N]"""
import re
import sys


def block(path, heading, lang, n=1):
    lines = open(path, encoding="utf-8").read().splitlines()
    under, seen, fenced = False, 0, False
    for i, line in enumerate(lines):
        if line.startswith("```"):
            fenced = not fenced
            if fenced and under and line.strip() == "```" + lang:
                seen += 1
                if seen == n:
                    return "\n".join(lines[i + 1:lines.index("```", i + 1)]) + "\n"
        elif not fenced and re.match(r"^#{1,3} ", line):
            under = line.lstrip("#").strip() == heading
    sys.exit(f"{path}: no ```{lang} block number {n} under the heading '{heading}'")


if __name__ == "__main__":
    if len(sys.argv) not in (4, 5):
        sys.exit(__doc__)
    sys.stdout.write(block(*sys.argv[1:4], *map(int, sys.argv[4:])))
