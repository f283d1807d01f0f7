#!/usr/bin/env python3
"""Check that the unity build (CLEARSHAPE_UNITY, on in `make run` and `make test`) still compiles.

A unity batch compiles up to 8 sources as one translation unit, so two sources of a batch must not
define the same file-local name (anonymous namespace, static, `using json = ...`). A build tree
made with plain `cmake` has the option off and never shows such a clash; this script does, without
building anything: it configures a throw-away tree (configure only, in a temporary folder), then
runs the compiler with -fsyntax-only on every unity batch, one at a time, at nice 19 (about 3 min
of CPU for everything, seconds for one target).

    scripts/check-unity.py                      # every target
    scripts/check-unity.py test_cli clearshape_study   # only these targets

Exit 0 when every batch compiles; 1 with the compiler's first errors otherwise. A clash is fixed
by renaming the file-local name, or by listing the file in the target's SKIP list
(cmake/ClearshapeModule.cmake, clearshape_unity()).
"""
import json
import re
import shlex
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def configure(tree: Path) -> list[dict]:
    """Configures `tree` as `make test` does (unity on, warnings are errors); its compile commands."""
    subprocess.run(["cmake", "-S", str(ROOT), "-B", str(tree), "-DCMAKE_BUILD_TYPE=Release",
                    "-DCMAKE_EXPORT_COMPILE_COMMANDS=ON", "-DCLEARSHAPE_UNITY=ON", "-DCLEARSHAPE_WERROR=ON",
                    "-DCLEARSHAPE_PCH=ON", "-DCLEARSHAPE_BUILD_TESTS=ON", "-DCLEARSHAPE_BUILD_EXAMPLES=ON",
                    "-DCLEARSHAPE_BUILD_BENCHMARKS=ON"], check=True, capture_output=True, text=True)
    return json.loads((tree / "compile_commands.json").read_text())


def syntax_only(entry: dict) -> subprocess.CompletedProcess:
    """The entry's compile command with -fsyntax-only and no output file."""
    args = shlex.split(entry["command"])
    for flag in ("-o", "-MF", "-MT"):
        while flag in args:
            i = args.index(flag)
            del args[i:i + 2]
    args = [a for a in args if a != "-MD"]
    return subprocess.run(["nice", "-n", "19", *args, "-fsyntax-only"], cwd=entry["directory"],
                          capture_output=True, text=True)


def main() -> int:
    targets = set(sys.argv[1:])
    failed = 0
    with tempfile.TemporaryDirectory(prefix="clearshape-unity-") as tmp:
        for entry in configure(Path(tmp)):
            match = re.search(r"CMakeFiles/([^/]+)\.dir/Unity/(unity_\d+_cxx\.cxx)$", entry["file"])
            if not match or (targets and match.group(1) not in targets):
                continue
            result = syntax_only(entry)
            sources = re.findall(r'#include "([^"]+)"', Path(entry["file"]).read_text())
            print(f"{match.group(1)} {match.group(2)}: {'ok' if result.returncode == 0 else 'FAILS'}", flush=True)
            if result.returncode != 0:
                failed += 1
                print("  batch: " + " ".join(Path(s).name for s in sources))
                errors = [line for line in result.stderr.splitlines() if "error" in line]
                print("\n".join("  " + line.replace(str(ROOT) + "/", "") for line in errors[:8]))
    print(f"{failed} unity batch(es) fail" if failed else "every unity batch compiles")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
