#!/usr/bin/env python3
"""Run every ```sh and ```python code block of README.md and docs/*.md as written (issue 20, item 6).

Each block runs in its own fresh temporary directory, so a block must make (or name a shipped file
for) every input it reads: a block that needs what another one made says so with the skip
annotation below. The directory holds copies of the repository's studies/, python/, scripts/,
examples/ and tests/golden/ (so nothing a command writes can reach the repository), the symbolic
link build/bin/clearshape to the CLI under test
and build/python (the Python module, when built); build/bin is first on PATH, so `clearshape` and
`build/bin/clearshape` are both the CLI under test.

A ```python block runs as one script with the interpreter the Python module was built for
(--python), build/python on PYTHONPATH; it must exit 0.

Annotations the docs carry, visible to readers, recognised here:
  - a comment line `# not run by the doc test: REASON` inside a block: the whole block is not run;
  - a trailing `# not run by the doc test: REASON` on a command: that command is not run;
  - a trailing `# exits N` on a command: it must exit with N (default 0); a comment line right under
    it that starts with `# clearshape` is the message it must print on stderr.
Every other command must exit 0. The script prints each block and command it ran or skipped with
the reason, and the totals; it exits 1 when a command exits otherwise than expected.

usage: run_doc_blocks.py --repo DIR --cli PATH [--python-build-dir DIR --python EXE] [--timeout-s 120] [DOC.md ...]
"""
import argparse
import glob
import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import tempfile
import time

SKIP_MARK = re.compile(r"not run by the doc test:\s*(.+?)\s*$")
EXIT_MARK = re.compile(r"#\s*exits\s+(\d+)\b")
FENCE = re.compile(r"^(\s*)```(\S*)\s*$")
HEREDOC = re.compile(r"<<-?\s*(['\"]?)(\w+)\1")
NEEDS_PYTHON_MODULE = ("build/python", "clearshape sweep ")  # docs/python.md; sweeps run clearshape.sweep
COPIED_DIRS = ("studies", "python", "scripts", "examples", os.path.join("tests", "golden"))


def sh_blocks(path, report, name):
    """The sh and python blocks of a Markdown file: (first body line, language, [lines]), the fence's indent removed.

    Other blocks are counted by language; a shell transcript (`$ command`) outside a sh block is an
    error, so a command cannot escape the test by its fence."""
    blocks, lines = [], open(path, encoding="utf-8").read().split("\n")
    i = 0
    while i < len(lines):
        fence = FENCE.match(lines[i])
        if not fence:
            i += 1
            continue
        indent, lang, start, body = fence.group(1), fence.group(2), i + 1, []
        i += 1
        while i < len(lines) and not re.match(r"^\s*```\s*$", lines[i]):
            body.append(lines[i][len(indent):] if lines[i].startswith(indent) else lines[i])
            i += 1
        if i == len(lines):
            raise SystemExit(f"{name}:{start}: code block never closed")
        if lang in ("sh", "bash", "shell", "python"):
            blocks.append((start + 1, lang, body))
        else:
            report["other_blocks"][lang or "no language"] = report["other_blocks"].get(lang or "no language", 0) + 1
            if any(line.lstrip().startswith("$ ") for line in body):
                report["failures"].append(f"{name}:{start}")
                print(f"FAIL  {name}:{start}: a shell transcript (`$ …`) in a ```{lang} block; make it a ```sh block")
        i += 1
    return blocks


def trailing_comment(line):
    """The text after an unquoted ` #` (the shell's comment), or ''."""
    quote, escaped = None, False
    for k, ch in enumerate(line):
        if escaped:
            escaped = False
        elif ch == "\\" and quote != "'":
            escaped = True
        elif quote:
            if ch == quote:
                quote = None
        elif ch in "'\"":
            quote = ch
        elif ch == "#" and (k == 0 or line[k - 1].isspace()):
            return line[k:]
    return ""


def commands(body):
    """Logical commands of a block: (first index, last index, comment) with continuations and heredocs joined."""
    out, i = [], 0
    while i < len(body):
        line = body[i]
        if not line.strip() or line.lstrip().startswith("#"):
            i += 1
            continue
        first = i
        while body[i].rstrip().endswith("\\") and i + 1 < len(body):
            i += 1
        comment = trailing_comment(body[i])
        heredoc = HEREDOC.search("\n".join(body[first:i + 1]).split("#")[0])
        if heredoc:
            while i + 1 < len(body) and body[i + 1].strip() != heredoc.group(2):
                i += 1
            i += 1
        out.append((first, i, comment))
        i += 1
    return out


def block_skip_reason(body):
    for line in body:
        if line.lstrip().startswith("#"):
            mark = SKIP_MARK.search(line)
            if mark:
                return mark.group(1)
    return None


def block_script(body, doc, first_line, report):
    """A bash script running the block's commands, each checked against its expected exit status."""
    script, ran = ["set -u", 'doc_test_stderr=$(mktemp -p "$PWD" .doc-test-stderr.XXXXXX)'], 0
    for first, last, comment in commands(body):
        where = f"{doc}:{first_line + first}"
        skip = SKIP_MARK.search(comment)
        if skip:
            report["skipped_lines"].append((where, skip.group(1)))
            print(f"  skip  {where}: {skip.group(1)}")
            continue
        expected = int(EXIT_MARK.search(comment).group(1)) if EXIT_MARK.search(comment) else 0
        script.append(f"echo '+ {where}' >&2")
        message = expected_message(body, last) if expected else None
        if message:  # the refusal the doc prints under the command must be the one the CLI gives
            script.extend(["{"] + body[first:last + 1] + ['} 2> "$doc_test_stderr"'])
            script.append(f"rc=$?; cat \"$doc_test_stderr\" >&2; grep -qF -- {shlex.quote(message)} "
                          f"\"$doc_test_stderr\" || {{ echo 'doc-test: {where} did not print the message the doc "
                          f"shows' >&2; exit 97; }}")
        else:
            script.extend(body[first:last + 1])
            script.append("rc=$?")
        script.append(f"if [ $rc -ne {expected} ]; then echo 'doc-test: {where} exited '$rc', "
                      f"expected {expected}' >&2; exit 97; fi")
        ran += 1
    return "\n".join(script) + "\n", ran


def python_script(body, python, where):
    """A bash script running a ```python block as one program (a python block is skipped whole or not at all)."""
    if any(SKIP_MARK.search(line) for line in body):
        raise SystemExit(f"{where}: a python block is run whole: put `# not run by the doc test: REASON` "
                         "on a line of its own, or run all of it")
    return f"{shlex.quote(python)} - <<'DOC_TEST_PYTHON'\n" + "\n".join(body) + "\nDOC_TEST_PYTHON\n"


def expected_message(body, last):
    """The comment line right under a command that declares its exit status, when it shows the CLI's message."""
    if last + 1 < len(body):
        shown = body[last + 1].strip()
        if shown.startswith("# clearshape"):
            return shown[2:]
    return None


def fresh_workdir(repo, cli, python_build_dir, parent):
    work = tempfile.mkdtemp(prefix="doc-", dir=parent)
    for sub in COPIED_DIRS:
        shutil.copytree(os.path.join(repo, sub), os.path.join(work, sub),
                        ignore=shutil.ignore_patterns("__pycache__"))
    os.makedirs(os.path.join(work, "build", "bin"))
    os.symlink(os.path.abspath(cli), os.path.join(work, "build", "bin", "clearshape"))
    if python_build_dir:
        os.symlink(os.path.abspath(python_build_dir), os.path.join(work, "build", "python"))
    return work


def run_script(script, work, env, timeout_s):
    """Exit status and the output's tail of one block; on a timeout its whole process group is ended."""
    proc = subprocess.Popen(["bash", "-c", script], cwd=work, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        out, err = proc.communicate(timeout=timeout_s)
        return proc.returncode, out[-3000:] + err[-3000:]
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.communicate()
        return "timeout", f"more than {timeout_s} s"


def run_doc(doc_path, args, parent, report):
    doc = os.path.relpath(doc_path, args.repo)
    blocks = sh_blocks(doc_path, report, doc)
    if not blocks:
        return
    for first_line, lang, body in blocks:
        where = f"{doc}:{first_line}"
        reason = block_skip_reason(body)
        if reason:
            report["skipped_blocks"].append((where, reason))
            print(f"SKIP  {where} (block): {reason}")
            continue
        needs_module = lang == "python" or any(needle in "\n".join(body) for needle in NEEDS_PYTHON_MODULE)
        if needs_module and not args.python_build_dir:
            report["skipped_blocks"].append((where, "the Python module is not built here"))
            print(f"SKIP  {where} (block): the Python module is not built here")
            continue
        if lang == "python":
            script, ran = python_script(body, args.python, where), 1
        else:
            script, ran = block_script(body, doc, first_line, report)
        if ran == 0:
            continue
        work = fresh_workdir(args.repo, args.cli, args.python_build_dir, parent)
        env = dict(os.environ, PATH=os.path.join(work, "build", "bin") + os.pathsep + os.environ["PATH"],
                   PYTHONDONTWRITEBYTECODE="1", MPLBACKEND="Agg")
        if args.python_build_dir:
            env["PYTHONPATH"] = os.path.join(work, "build", "python")
        start = time.monotonic()
        status, log = run_script(script, work, env, args.timeout_s)
        elapsed = time.monotonic() - start
        shutil.rmtree(work)
        report["ran_blocks"] += 1
        report["ran_lines"] += ran
        if status == 0:
            print(f"ok    {where}: {ran} command(s), {elapsed:.1f} s")
        else:
            report["failures"].append(where)
            print(f"FAIL  {where}: {ran} command(s), {elapsed:.1f} s, status {status}\n{log}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repo", required=True)
    parser.add_argument("--cli", required=True)
    parser.add_argument("--python-build-dir", default="")
    parser.add_argument("--python", default=sys.executable, help="the interpreter of ```python blocks")
    parser.add_argument("--timeout-s", type=float, default=120)
    parser.add_argument("docs", nargs="*")
    args = parser.parse_args()
    docs = args.docs or [os.path.join(args.repo, "README.md")] + sorted(glob.glob(os.path.join(args.repo, "docs", "*.md")))
    report = {"ran_blocks": 0, "ran_lines": 0, "skipped_blocks": [], "skipped_lines": [], "failures": [],
              "other_blocks": {}}
    start = time.monotonic()
    with tempfile.TemporaryDirectory(prefix="clearshape-doc-test-") as parent:
        for doc in docs:
            run_doc(doc, args, parent, report)
    print(f"\n{report['ran_blocks']} block(s) run ({report['ran_lines']} command(s)), "
          f"{len(report['skipped_blocks'])} block(s) and {len(report['skipped_lines'])} command(s) not run "
          f"(reasons above), {len(report['failures'])} failed, {time.monotonic() - start:.1f} s")
    others = ", ".join(f"{n} {lang}" for lang, n in sorted(report["other_blocks"].items()))
    print(f"not commands (not run): {others or 'none'} block(s)")
    if report["ran_blocks"] == 0:
        print("no block ran: nothing was checked")
        return 1
    return 1 if report["failures"] else 0


if __name__ == "__main__":
    sys.exit(main())
