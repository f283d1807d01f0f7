"""Colour and line style per signal role, and axis units read from column names.

One role, one look, in every figure of the report: the command is black and dashed, the unshaped
response vermillion, each shaper its own colour (ZVDD green, as in the thesis's figures where the
shaped response is green), rig measurements dark grey, model/simulation purple, the thesis's
published numbers grey and hatched. Colours are the Okabe–Ito colour-blind-safe set.
"""
from __future__ import annotations

import re

ROLE_STYLES: dict[str, dict] = {
    "command": {"color": "#1a1a1a", "linestyle": (0, (4, 2)), "linewidth": 1.1, "zorder": 5},
    "shaped_command": {"color": "#555555", "linestyle": (0, (1, 1.5)), "linewidth": 1.1, "zorder": 5},
    "unshaped": {"color": "#D55E00", "linestyle": "-", "linewidth": 1.4, "zorder": 3},
    "zv": {"color": "#56B4E9", "linestyle": "-", "linewidth": 1.3, "zorder": 4},
    "zvd": {"color": "#E69F00", "linestyle": "-", "linewidth": 1.3, "zorder": 4},
    "zvdd": {"color": "#009E73", "linestyle": "-", "linewidth": 1.5, "zorder": 4},
    "zvddd": {"color": "#004D40", "linestyle": "-", "linewidth": 1.3, "zorder": 4},
    "mzv": {"color": "#0072B2", "linestyle": "-", "linewidth": 1.3, "zorder": 4},
    "ei": {"color": "#CC79A7", "linestyle": "-", "linewidth": 1.3, "zorder": 4},
    "ei2": {"color": "#8C564B", "linestyle": "-", "linewidth": 1.3, "zorder": 4},
    "ei3": {"color": "#7F7F7F", "linestyle": "-", "linewidth": 1.3, "zorder": 4},
    "si": {"color": "#B8860B", "linestyle": "-", "linewidth": 1.3, "zorder": 4},
    "umzv": {"color": "#6A3D9A", "linestyle": "-", "linewidth": 1.3, "zorder": 4},
    # clearshape's own designs on the fitted clearance model (Tol's wine and olive: no collision with the
    # unshaped vermillion or MZV's blue)
    "clearanceaware": {"color": "#882255", "linestyle": "-", "linewidth": 1.3, "zorder": 4},
    "takeup": {"color": "#999933", "linestyle": "-", "linewidth": 1.3, "zorder": 4},
    "measured": {"color": "#404040", "linestyle": "-", "linewidth": 1.2, "zorder": 3},
    "model": {"color": "#7B3FA0", "linestyle": (0, (5, 1.5)), "linewidth": 1.4, "zorder": 4},
    "thesis": {"color": "#9E9E9E", "linestyle": ":", "linewidth": 1.2, "zorder": 2},
    "mean": {"color": "#332288", "linestyle": (0, (6, 2)), "linewidth": 1.2, "zorder": 6},  # no design's colour
    "trial": {"color": "#404040", "linestyle": "-", "linewidth": 0.8, "zorder": 2},
    "marker": {"color": "#D55E00", "linestyle": "none", "linewidth": 1.0, "zorder": 7},
}

# Bars of the thesis's numbers beside ours: grey, hatched.
THESIS_BAR = {"color": "#E0E0E0", "edgecolor": "#7A7A7A", "hatch": "////"}

SHAPER_ORDER = ["unshaped", "zv", "zvd", "zvdd", "zvddd", "mzv", "ei", "ei2", "ei3", "si", "umzv", "clearanceaware",
                "takeup"]

SHAPER_LABELS = {
    "unshaped": "without IS", "zv": "ZV", "zvd": "ZVD", "zvdd": "ZVDD", "zvddd": "ZVDDD", "mzv": "MZV", "ei": "EI",
    "ei2": "EI2", "ei3": "EI3", "si": "SI", "umzv": "UM-ZV", "clearanceaware": "clearance-aware",
    "takeup": "take-up", "command": "command",
    "shaped_command": "shaped command", "measured": "rig (measured)", "model": "model (simulated)",
    "thesis": "thesis", "mean": "mean",
}

# Curves that are no design (inputs of one figure, unnamed signals): colours no design uses (Tol's indigo
# and brown) told apart by line style, so a blue or vermillion curve always means MZV or "without IS".
_FALLBACK = [("#332288", "-"), ("#661100", "--"), ("#332288", ":"), ("#661100", "-."),
             ("#332288", "--"), ("#661100", "-"), ("#332288", "-."), ("#661100", ":")]


def design_colours() -> set:
    """The colours reserved for the designs (each shaper and the unshaped response), in lower-case hex."""
    return {st["color"].lower() for r, st in ROLE_STYLES.items() if r in SHAPER_ORDER}


def normalise_role(role: str | None) -> str:
    """Lower-case role name with separators removed ("ZV-D" → "zvd", "without" → "unshaped")."""
    if not role:
        return ""
    r = re.sub(r"[\s_\-]", "", str(role).lower())
    aliases = {"none": "unshaped", "without": "unshaped", "withoutis": "unshaped", "raw": "unshaped",
               "sim": "model", "simulated": "model", "simulation": "model", "rig": "measured",
               "experiment": "measured", "shapedcommand": "shaped_command", "commandshaped": "shaped_command"}
    return aliases.get(r, r)


# The mode a shaper was designed for (docs/design.md §2): the link's identified residual mode draws solid,
# the drive model (Eq. 4.2) dashed, so both ZVDD variants stay visible over the unshaped response.
SOURCE_LINESTYLE = {"link-mode": "-", "drive-model": (0, (5, 2))}


def style_for(role: str | None, index: int = 0, source: str = "") -> dict:
    """Line style for a role (and shaper mode source); unknown roles take the fallback cycle by index."""
    r = normalise_role(role)
    if r in ROLE_STYLES:
        st = dict(ROLE_STYLES[r])
        if source in SOURCE_LINESTYLE and r not in ("command", "unshaped", "measured", "model"):
            st["linestyle"] = SOURCE_LINESTYLE[source]
            if source == "drive-model":  # thin dashes over the unshaped line it often coincides with
                st["zorder"], st["linewidth"] = 3.5, 1.0
        return st
    colour, linestyle = _FALLBACK[index % len(_FALLBACK)]
    return {"color": colour, "linestyle": linestyle, "linewidth": 1.2, "zorder": 3}


def label_for(role: str | None) -> str:
    r = normalise_role(role)
    return SHAPER_LABELS.get(r, str(role) if role else "")


# Unit suffixes of CSV column names (docs/design.md §4: time_s, command_deg, gyro_deg_s, ...), longest first.
_UNITS = [
    ("_deg_s2", "°/s²"), ("_rad_s2", "rad/s²"), ("_deg_s", "°/s"), ("_rad_s", "rad/s"), ("_n_m", "N·m"),
    ("_deg", "°"), ("_rad", "rad"), ("_hz", "Hz"), ("_ms", "ms"), ("_s", "s"), ("_v", "V"),
    ("_pct", "%"), ("_percent", "%"), ("_m", "m"), ("_1", "1"),
]


def unit_from_column(column: str) -> str:
    """Unit implied by a column name's suffix ("gyro_deg_s" → "°/s"); "" when none is recognised."""
    c = column.lower()
    for suffix, unit in _UNITS:
        if c.endswith(suffix):
            return unit
    return ""


def quantity_from_column(column: str) -> str:
    """Readable quantity from a column name without its unit suffix ("gyro_deg_s" → "gyro")."""
    c = column
    for suffix, _ in _UNITS:
        if c.lower().endswith(suffix):
            c = c[: -len(suffix)]
            break
    return c.replace("_", " ")


def axis_label(label: str | None, unit: str | None, column: str | None = None) -> str:
    """"quantity (unit)"; the unit comes from the spec or else from the column suffix; "1" = dimensionless."""
    if not label and column:
        label = quantity_from_column(column)
    if not unit and column:
        unit = unit_from_column(column)
    unit = pretty_unit(unit or "")
    if unit in ("", "1"):
        unit = "–"
    return f"{label} ({unit})" if label else f"({unit})"


def pretty_unit(unit: str) -> str:
    """deg → °, deg/s → °/s, dimensionless → "–"."""
    u = str(unit).strip()
    if u.lower().startswith("dimensionless") or u in ("1", "-", "—"):
        return "–"
    return u.replace("deg/s", "°/s").replace("deg_s", "°/s").replace("deg", "°")


def label_with_unit(text: str | None, column: str | None = None) -> str:
    """An axis label that always ends in a unit: "motor angle (deg)" → "motor angle (°)"; a label
    without "(unit)" takes the unit of the column's suffix, or "(–)" when dimensionless."""
    if not text:
        return axis_label(None, None, column)
    m = re.match(r"^(.*?)\s*\(([^()]*)\)\s*$", str(text))
    if m:
        return f"{m.group(1)} ({pretty_unit(m.group(2))})"
    return axis_label(str(text), unit_from_column(column) if column else None)


SHAPER_TOKEN = re.compile(r"(?:^|_)(none|zv|zvd|zvdd|zvddd|mzv|ei|ei2|ei3|si|umzv|um-zv|clearance-aware|take-up)"
                          r"(?:@([A-Za-z0-9_-]+))?$", re.I)


def infer_role(column: str, label: str | None = None) -> tuple[str, str]:
    """(role, mode source) of a study CSV column: "md_signal_zvdd@link-mode" → ("zvdd", "link-mode"),
    "command_none" → ("command", ""), "run03_motor_angle_deg" → ("trial", ""), "model_deg" → ("model", "")."""
    c = str(column)
    low = c.lower()
    if re.match(r"^run\d+_", low):
        return "trial", ""
    m = SHAPER_TOKEN.search(c)
    if m:
        shaper = normalise_role(m.group(1))
        source = m.group(2) or ""
        if low.startswith("command"):
            return ("command", "") if shaper == "unshaped" else (shaper, source)
        return shaper, source
    if low.startswith("command"):
        return "command", ""
    if re.search(r"(^|_)(model|fitted|simulated)(_|$)", low):
        return "model", ""
    if re.search(r"(^|_)(measured|gyro|encoder|experiment)(_|$)", low):
        return "measured", ""
    return "", ""
