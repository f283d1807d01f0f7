"""The sweep file (SWEEP.toml, docs/sweeps.md): what varies, over what, and the points it gives.

A point is one simulated comparison: the rig truth, the command and the shaper fixed, the
command run unshaped and shaped. Every point is a dict of the PARAMETERS below; the points of a
sweep are the grid (Cartesian product, in file order) times `samples` Monte-Carlo draws
(uniform in [low, high], from numpy's PCG64 seeded with [sweep] seed) — or the grid alone.
"""
import hashlib
import itertools
import json
import tomllib

import numpy as np

# name: (kind, default, allowed range or names, meaning with unit)
PARAMETERS = {
    "truth": ("name", "thesis", "truths", "built-in rig truth (clearshape.truth_names())"),
    "mode": ("name", "position", ("position", "speed"), "drive mode"),
    "clearance_deg": ("number", None, (0.0, 20.0), "total play 2β (deg); default: the truth's"),
    "contact_stiffness": ("number", None, (1e-6, 1e12), "flank stiffness K (N·m/rad^n); default: the truth's"),
    "contact_damping": ("number", None, (0.0, 1e6), "flank damping D (N·m·s/rad); default: the truth's"),
    "link_inertia_kg_m2": ("number", None, (1e-7, 10.0), "link inertia J (kg·m²); default: the truth's"),
    "variation_scale": ("number", 0.0, (0.0, 10.0),
                        "run-to-run variation: 0 = the nominal rig (offline run); s > 0 = the truth's σs × s, "
                        "drawn per run on a SimRig"),
    "signal": ("name", "step", "signals", "command signal type (clearshape.signal_types())"),
    "amplitude": ("number", 20.0, (-1e4, 1e4), "command amplitude (deg in position mode, V in speed mode)"),
    "start_s": ("number", 0.1, (0.0, 100.0), "when the command starts (s)"),
    "rise_s": ("number", 0.0, (0.0, 100.0), "finite rise of step-like signals (s)"),
    "shaper": ("name", "zvd", "shapers", "shaper method: zv, zvd, zvdd, zvddd, mzv, ei, ei2, ei3, um-zv"),
    "design_frequency_hz": ("number", None, (1e-3, 1e4), "the mode the shaper is designed for (Hz); required"),
    "frequency_error": ("number", 0.0, (-0.9, 10.0),
                        "relative error of the design frequency: designed at f·(1 + error)"),
    "zeta": ("number", 0.0, (0.0, 0.999), "damping ratio the shaper is designed for"),
    "vtol": ("number", 0.05, (1e-4, 0.99), "Vtol of ei/ei2/ei3"),
}
SETTINGS = {  # [sweep] table
    "seed": ("integer", 1, (0, 2**63 - 1), "seed of the Monte-Carlo draws and of every run"),
    "samples": ("integer", 0, (0, 10**7), "Monte-Carlo draws per grid point (0: the grid alone)"),
    "duration_s": ("number", 3.0, (0.1, 100.0), "simulated time per run (s)"),
    "rate_hz": ("number", 1000.0, (10.0, 1e5), "sample rate of the command and the output (Hz)"),
    "batch": ("integer", 8, (1, 10**6), "points per task"),
    "plot": ("axes", [], None, "two varying parameters: DIR/improvement_map.png over them"),
}


class SweepError(ValueError):
    """A bad sweep file: the message names the file, the table.field and the allowed values."""


# What one point costs while a sweep runs: its parameters, its result and its table row held in
# memory (measured ~0.5 kB for a point's dict; the result and the row take more), and the
# simulated samples of its two runs (unshaped and shaped).
POINT_BYTES = 2048
MAX_POINTS = 1_000_000  # the default limit (--max-points): about 2 GB and 2·10⁶ simulated runs


def _check(path, where, kind, allowed, value):
    if kind == "name":
        if not isinstance(value, str):
            raise SweepError(f"{path}: {where} = {value!r} must be a name (text)")
        if isinstance(allowed, str):  # names the C++ library knows
            from . import _core
            allowed = {"truths": _core.truth_names(), "signals": _core.signal_types(),
                       "shapers": [m for m in _core.shaper_methods() if m not in ("si", "custom")]}[allowed]
        if allowed and value not in allowed:
            raise SweepError(f"{path}: {where} = {value!r} is not known; allowed: {', '.join(allowed)}")
        return value
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise SweepError(f"{path}: {where} = {value!r} must be a number")
    if kind == "integer" and not float(value).is_integer():
        raise SweepError(f"{path}: {where} = {value!r} must be a whole number")
    lo, hi = allowed
    if not (lo <= value <= hi):
        raise SweepError(f"{path}: {where} = {value!r} is out of range; allowed: [{lo:g}, {hi:g}]")
    return int(value) if kind == "integer" else float(value)


class Sweep:
    """A parsed, validated sweep file."""

    def __init__(self, text, path="SWEEP.toml"):
        try:
            doc = tomllib.loads(text)
        except tomllib.TOMLDecodeError as e:
            raise SweepError(f"{path}: {e}") from None
        unknown = set(doc) - {"sweep", "fixed", "grid", "random"}
        if unknown:
            raise SweepError(f"{path}: unknown table [{sorted(unknown)[0]}]; allowed: [sweep], [fixed], [grid], [random]")
        self.path = path
        self.text = text
        self.settings = {k: v[1] for k, v in SETTINGS.items()}
        for key, value in doc.get("sweep", {}).items():
            if key not in SETTINGS:
                raise SweepError(f"{path}: sweep.{key} is not known; allowed: {', '.join(SETTINGS)}")
            kind, _, allowed, _ = SETTINGS[key]
            if kind == "axes":
                if not (isinstance(value, list) and len(value) == 2 and all(isinstance(v, str) for v in value)):
                    raise SweepError(f"{path}: sweep.{key} must be two parameter names, e.g. [\"clearance_deg\", \"frequency_error\"]")
                self.settings[key] = list(value)
                continue
            self.settings[key] = _check(path, f"sweep.{key}", kind, allowed, value)
        self.fixed, self.grid, self.random = {}, {}, {}
        seen = {}
        for table in ("fixed", "grid", "random"):
            for key, value in doc.get(table, {}).items():
                if key not in PARAMETERS:
                    raise SweepError(f"{path}: {table}.{key} is not known; allowed: {', '.join(PARAMETERS)}")
                if key in seen:
                    raise SweepError(f"{path}: {table}.{key} is also in [{seen[key]}]; give a parameter once")
                seen[key] = table
                kind, _, allowed, _ = PARAMETERS[key]
                if table == "fixed":
                    self.fixed[key] = _check(path, f"fixed.{key}", kind, allowed, value)
                elif table == "grid":
                    if not isinstance(value, list) or not value:
                        raise SweepError(f"{path}: grid.{key} must be a non-empty list")
                    self.grid[key] = [_check(path, f"grid.{key}[{i}]", kind, allowed, v) for i, v in enumerate(value)]
                else:
                    if kind != "number" or not isinstance(value, list) or len(value) != 2:
                        raise SweepError(f"{path}: random.{key} must be [low, high] of a numeric parameter")
                    lo, hi = (_check(path, f"random.{key}", kind, allowed, v) for v in value)
                    if not lo < hi:
                        raise SweepError(f"{path}: random.{key} = [{lo}, {hi}] needs low < high")
                    self.random[key] = (lo, hi)
        if "design_frequency_hz" not in seen:
            raise SweepError(f"{path}: design_frequency_hz (the mode the shaper is designed for, Hz) is required "
                             "in [fixed], [grid] or [random]")
        for axis in self.settings["plot"]:
            if axis not in self.grid and axis not in self.random:
                raise SweepError(f"{path}: sweep.plot names {axis!r}, which does not vary; "
                                 f"allowed: {', '.join(self.axes()) or 'no parameter varies'}")
        if self.random and self.settings["samples"] == 0:
            raise SweepError(f"{path}: [random] needs sweep.samples >= 1 (draws per grid point)")

    @classmethod
    def load(cls, path):
        with open(path, "rb") as f:
            raw = f.read()
        if raw.startswith(b"\xef\xbb\xbf"):
            raw = raw[3:]
        try:
            return cls(raw.decode("utf-8"), str(path))
        except UnicodeDecodeError as e:
            raise SweepError(f"{path}: not UTF-8 ({e})") from None

    def digest(self):
        """SHA-256 of what decides the results (the settings and parameters, not the file's layout)."""
        settings = {k: v for k, v in self.settings.items() if k != "plot"}  # a plot changes no result
        key = {"settings": settings, "fixed": self.fixed, "grid": self.grid,
               "random": {k: list(v) for k, v in self.random.items()}}
        return hashlib.sha256(json.dumps(key, sort_keys=True).encode()).hexdigest()

    def count(self):
        """How many points the sweep has (grid size × draws), without making them."""
        n = 1
        for values in self.grid.values():
            n *= len(values)
        return n * max(1, self.settings["samples"])

    def estimate(self):
        """The sweep's work and memory before anything runs: points, simulated runs and samples,
        and the bytes the point list and results take (POINT_BYTES each)."""
        points = self.count()
        per_run = int(round(self.settings["duration_s"] * self.settings["rate_hz"])) + 1
        return {"points": points, "runs": 2 * points, "samples": 2 * points * per_run,
                "memory_bytes": points * POINT_BYTES}

    def describe_estimate(self):
        e = self.estimate()
        shape = " × ".join(str(len(v)) for v in self.grid.values()) or "1"
        draws = max(1, self.settings["samples"])
        return (f"{e['points']:,} points (grid {shape} × {draws} draw{'s' if draws > 1 else ''}), "
                f"{e['runs']:,} simulated runs of {self.settings['duration_s']:g} s at "
                f"{self.settings['rate_hz']:g} Hz = {e['samples']:.3g} samples, "
                f"about {e['memory_bytes'] / 1e6:,.0f} MB of memory")

    def check_size(self, max_points=MAX_POINTS):
        """Raises SweepError with the numbers when the sweep has more than `max_points` points."""
        points = self.count()
        if points > max_points:
            raise SweepError(f"{self.path}: the sweep is too large: {self.describe_estimate()}; the limit is "
                             f"{max_points:,} points — shrink [grid] or sweep.samples, or allow it with "
                             f"--max-points {points}")

    def points(self):
        """Every point: a dict of every parameter (defaults filled), plus index and seed."""
        defaults = {k: v[1] for k, v in PARAMETERS.items()}
        rng = np.random.Generator(np.random.PCG64(self.settings["seed"]))
        seeds = np.random.Generator(np.random.PCG64([self.settings["seed"], 1]))
        names = list(self.grid)
        draws = max(1, self.settings["samples"])
        out = []
        for combo in itertools.product(*(self.grid[n] for n in names)):
            for _ in range(draws):
                p = dict(defaults)
                p.update(self.fixed)
                p.update(zip(names, combo))
                for key, (lo, hi) in self.random.items():
                    p[key] = float(rng.uniform(lo, hi))
                p["index"] = len(out)
                p["seed"] = int(seeds.integers(1, 2**62))
                out.append(p)
        return out

    def axes(self):
        """The parameters that vary (grid first, then random), for the summary plots."""
        return list(self.grid) + list(self.random)
