"""Reading a study output folder: CSV runs (one header line, unit-suffixed columns) and JSON files."""
from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np


class StudyDataError(Exception):
    """A file or column the figure index names is missing or unreadable (message names which)."""


def read_json(path: Path) -> dict:
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except FileNotFoundError:
        raise StudyDataError(f"{path}: file not found") from None
    except json.JSONDecodeError as e:
        raise StudyDataError(f"{path}:{e.lineno}: invalid JSON: {e.msg}") from None


class CsvCache:
    """Reads each CSV once; columns by name as float arrays."""

    def __init__(self, root: Path):
        self.root = Path(root)
        self._tables: dict[Path, dict[str, np.ndarray]] = {}

    def table(self, file: str) -> dict[str, np.ndarray]:
        path = (self.root / file).resolve()
        if path not in self._tables:
            self._tables[path] = _read_csv(path)
        return self._tables[path]

    def column(self, file: str, name: str) -> np.ndarray:
        t = self.table(file)
        if name not in t:
            raise StudyDataError(f"{self.root / file}: no column '{name}' (columns: {', '.join(t)})")
        return t[name]


def _read_csv(path: Path) -> dict[str, np.ndarray]:
    try:
        with open(path, newline="", encoding="utf-8") as f:
            header = next(csv.reader(f))
    except FileNotFoundError:
        raise StudyDataError(f"{path}: file not found") from None
    except StopIteration:
        raise StudyDataError(f"{path}: empty file") from None
    header = [h.strip() for h in header]
    try:
        values = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2, dtype=float)
    except ValueError as e:
        raise StudyDataError(f"{path}: {e}") from None
    if values.shape[0] == 0:
        raise StudyDataError(f"{path}: header but no rows")
    if values.shape[1] != len(header):
        raise StudyDataError(f"{path}: {len(header)} header fields but {values.shape[1]} columns")
    return {name: values[:, i] for i, name in enumerate(header)}
