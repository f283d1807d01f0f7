"""The type stub clearshape/__init__.pyi (PEP 561, with py.typed) against the built module: every
public name of the module is in the stub and every name of the stub in the module; each function's
and method's parameters (names, order, keyword-only, which have defaults) are those of the
signature pybind11 gives for the C++ binding; and the committed stub is what
scripts/gen-python-stubs.py writes today (a binding added without regenerating fails here)."""
import ast
import os
import re
import subprocess
import sys
from pathlib import Path

import clearshape

REPO = Path(__file__).resolve().parents[2]
STUB = REPO / "bindings" / "python" / "clearshape" / "__init__.pyi"


def stub_tree():
    return ast.parse(STUB.read_text(encoding="utf-8"), filename=str(STUB))


def top_level_names(tree):
    names = set()
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, ast.AnnAssign):
            names.add(node.target.id)
    return names


def public_names():
    return {n for n in dir(clearshape) if not n.startswith("_") and type(getattr(clearshape, n)).__name__ != "module"}


def pybind_parameters(doc, name, method):
    """[(name, has_default, keyword_only)] of each signature line pybind11 wrote for `name`."""
    out = []
    for line in doc.splitlines():
        m = re.match(rf"^(?:\d+\. )?{re.escape(name)}\((.*)\)", line)
        if not m or "*args, **kwargs" in m.group(1) and "Overloaded" in doc:
            continue
        params, kw_only = [], False
        # a parameter starts at a name followed by ':' at the top level; '*' alone marks keyword-only
        depth, start, text = 0, 0, m.group(1) + ","
        for i, ch in enumerate(text):
            depth += ch in "[({<"
            depth -= ch in "])}>"
            if ch == "," and depth == 0:
                part = text[start:i].strip()
                start = i + 1
                if part == "*":
                    kw_only = True
                elif part.startswith("**"):
                    params.append((part[2:].split(":")[0], False, "**"))
                elif part:
                    params.append((part.split(":")[0].strip(), "=" in part, kw_only))
        out.append(params[1:] if method else params)
    return out


def stub_parameters(fn, method):
    a = fn.args
    positional = a.args[1:] if method else a.args
    first_default = len(positional) - len(a.defaults)
    params = [(p.arg, i >= first_default, False) for i, p in enumerate(positional)]
    params += [(p.arg, d is not None, True) for p, d in zip(a.kwonlyargs, a.kw_defaults)]
    if a.kwarg:
        params.append((a.kwarg.arg, False, "**"))
    return params


def test_stub_and_module_name_the_same_things():
    tree = stub_tree()
    names = top_level_names(tree)
    assert public_names() - names == set(), "in the module, not in the stub"
    assert names - public_names() - {"__version__"} == set(), "in the stub, not in the module"
    assert (STUB.parent / "py.typed").is_file()


def test_every_signature_matches_the_binding():
    checked = 0
    for node in stub_tree().body:
        if isinstance(node, ast.FunctionDef):
            expected = pybind_parameters(getattr(clearshape, node.name).__doc__, node.name, method=False)
            assert stub_parameters(node, method=False) in expected, node.name
            checked += 1
        elif isinstance(node, ast.ClassDef):
            cls = getattr(clearshape, node.name)
            members = {n.name if isinstance(n, ast.FunctionDef) else n.target.id for n in node.body
                       if isinstance(n, (ast.FunctionDef, ast.AnnAssign))}
            public = {n for n in vars(cls) if not n.startswith("_")}
            assert public <= members, (node.name, public - members)
            for fn in (n for n in node.body if isinstance(n, ast.FunctionDef)):
                member = vars(cls)[fn.name]
                if isinstance(member, property):
                    continue
                expected = pybind_parameters(member.__doc__, fn.name, method=True)
                assert stub_parameters(fn, method=True) in expected, (node.name, fn.name)
                checked += 1
    assert checked >= 45  # every function and method, not a few


def test_committed_stub_is_what_the_generator_writes():
    r = subprocess.run([sys.executable, str(REPO / "scripts" / "gen-python-stubs.py"), "--check"],
                       env=dict(os.environ), capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


def test_stub_is_copied_beside_the_module_in_the_build_tree():
    built = Path(clearshape.__file__).parent
    assert (built / "__init__.pyi").read_text(encoding="utf-8") == STUB.read_text(encoding="utf-8")
    assert (built / "py.typed").is_file()
