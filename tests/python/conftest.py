"""Shared fixtures: the CLI (the C++ reference the bindings are compared with) and CSV helpers."""
import csv
import json
import os
import subprocess

import numpy as np
import pytest


@pytest.fixture(scope="session")
def cli():
    """Runs `clearshape ARGS…`; returns stdout (text), raises on a non-zero exit."""
    exe = os.environ.get("CLEARSHAPE_CLI")
    if not exe:
        pytest.fail("CLEARSHAPE_CLI is not set (ctest sets it to the built CLI)")

    def run(*args, expect=0):
        r = subprocess.run([exe, *map(str, args)], capture_output=True, text=True)
        if r.returncode != expect:
            raise AssertionError(f"clearshape {' '.join(map(str, args))}: exit {r.returncode}\n{r.stderr}")
        return r.stdout if expect == 0 else r.stderr

    return run


@pytest.fixture(scope="session")
def cli_json(cli):
    return lambda *args: json.loads(cli(*args, "--json"))


def read_csv(path):
    """Columns of a CSV by name, parsed exactly (the CLI writes shortest round-trip numbers)."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    return {name: np.array([float(r[i]) for r in body]) for i, name in enumerate(header)}


def write_csv(path, columns):
    names = list(columns)
    n = len(columns[names[0]])
    with open(path, "w", newline="") as f:
        f.write(",".join(names) + "\n")
        for i in range(n):
            f.write(",".join(repr(float(columns[c][i])) for c in names) + "\n")


def deg_to_rad(x):
    """As clearshape::deg_to_rad (x·π, then /180), so the same bits reach the C++."""
    return np.asarray(x, dtype=float) * np.pi / 180.0


def rad_to_deg(x):
    return np.asarray(x, dtype=float) * 180.0 / np.pi
