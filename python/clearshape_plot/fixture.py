"""A small synthetic study output folder in the shape `clearshape study` writes
(docs/study-outputs.md), for testing the figures and the report without running the study.

    /usr/bin/python3 -m clearshape_plot.fixture <out> [--trials N]      (with PYTHONPATH=python)

The numbers are made up (seeded, deterministic): closed-form responses plus noise, not
simulations, and results.json says so ("synthetic": true, rig "synthetic fixture"). Only the
shape of the folder matters: results.json, figures.json, tables.md and data/*.csv.
"""
from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np

from . import thesis

RATE_HZ = 1000.0


def _write_csv(path: Path, columns: dict) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    names = list(columns)
    data = np.column_stack([columns[n] for n in names])
    lines = [",".join(names)] + [",".join(f"{v:.9g}" for v in row) for row in data]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def _ramp(t, amplitude, rise_s=0.034, start_s=0.5):
    return amplitude * np.clip((t - start_s) / rise_s, 0.0, 1.0)


def _ring(cmd, t, freq_hz=15.0, zeta=0.13, ring=1.0):
    """The command through a fast lag plus a decaying ringing excited by its slope changes."""
    dt = t[1] - t[0]
    y = np.zeros_like(cmd)
    for i in range(1, len(t)):
        y[i] = y[i - 1] + dt / 0.01 * (cmd[i - 1] - y[i - 1])
    wn = 2 * math.pi * freq_hz
    tk = t - t[0]
    kernel = np.exp(-zeta * wn * tk) * np.sin(wn * math.sqrt(1 - zeta ** 2) * tk)
    accel = np.diff(cmd, 2, prepend=cmd[0], append=cmd[-1])
    return y + ring * 0.02 * np.convolve(accel, kernel)[: len(cmd)] / dt


def _zvdd(cmd, t, freq_hz=15.0, zeta=0.13):
    k = math.exp(-zeta * math.pi / math.sqrt(1 - zeta ** 2))
    amps = np.array([1, 3 * k, 3 * k * k, k ** 3]) / (1 + k) ** 3  # Singer & Seering ZVDD
    half = 0.5 / (freq_hz * math.sqrt(1 - zeta ** 2))
    n = [int(round(j * half * RATE_HZ)) for j in range(4)]
    out = np.zeros_like(cmd)
    for a, s in zip(amps, n):
        out[s:] += a * cmd[: len(cmd) - s]
    return out


def _md(t, y, start_s=0.5):
    from .figures import steady_state_mean_deviation
    md, m, k = steady_state_mean_deviation(t, y, search_from_s=start_s)
    return md, m, float(t[k])


def write_fixture(out: Path, trials: int = 3, seed: int = 7) -> Path:
    out = Path(out)
    (out / "data").mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, 2.0, 1.0 / RATE_HZ)
    figures, tables = [], []
    xs = {"column": "time_s", "label": "time (s)"}

    # Consistency (Table 4.2, Fig. 4.7).
    cmd = _ramp(t, 20.0)
    runs = [_ring(cmd, t, ring=0.0) + rng.normal(0, 0.003, t.size) for _ in range(trials)]
    _write_csv(out / "data/consistency_step-20.csv",
               {"time_s": t, **{f"run{i + 1:02d}_motor_angle_deg": r for i, r in enumerate(runs)}})
    m = np.mean(runs, axis=0)
    errs = [float(np.sqrt(np.mean((m - r) ** 2)) / (m.max() - m.min())) for r in runs]
    tables.append({"id": "4.2", "kind": "consistency", "title": f"Eq. 4.1 error of each of {trials} repeated runs",
                   "unit": "dimensionless", "row_labels": [str(i + 1) for i in range(trials)],
                   "columns": [{"key": "step-20", "label": "Step 20°", "ours": errs, "ours_mean": float(np.mean(errs)),
                                "ours_std": float(np.std(errs, ddof=1)), "thesis": thesis.TABLE_4_2["step"],
                                "thesis_mean": thesis.TABLE_4_2_MEAN["step"]}]})
    figures.append({"id": "consistency-step-20", "thesis_figure": "4.7", "kind": "time-series",
                    "title": f"{trials} runs of the Step 20° (encoder, deg)", "file": "data/consistency_step-20.csv",
                    "x": xs, "y_label": "motor angle (deg)",
                    "series": [{"column": f"run{i + 1:02d}_motor_angle_deg", "label": f"run {i + 1}"}
                               for i in range(trials)]})

    # Identification (Eq. 4.2 table, Fig. 4.17).
    _write_csv(out / "data/identification_step-20.csv",
               {"time_s": t, "measured_deg": runs[0], "model_deg": _ring(cmd, t, ring=0.0)})
    figures.append({"id": "identification-step-20", "thesis_figure": "4.17", "kind": "time-series",
                    "title": "Identified model and experiment, Step 20°", "file": "data/identification_step-20.csv",
                    "x": xs, "y_label": "motor angle (deg)",
                    "series": [{"column": "measured_deg", "label": "experiment"},
                               {"column": "model_deg", "label": "identified model"}]})
    th = thesis.EQ_4_2["position"]
    ours = [th["K"] * 0.999, th["Tz_s"] * 1.3, th["zeta"] * 0.99, th["Tw_s"] * 1.02, th["Tp3_s"] * 1.4]
    tables.append({"id": "4.2-model", "kind": "parameters", "title": "Identified drive model, Eq. 4.2",
                   "unit": "", "row_labels": ["Kp (deg/deg)", "Tz (s)", "Zeta (-)", "Tw (s)", "Tp3 (s)"],
                   "headline": {"selected_input": "step-20"},
                   "columns": [{"key": "step-20", "label": "Step 20° (selected)", "ours": ours,
                                "ours_std": [1e-5, 5e-4, 3e-3, 1e-4, 4e-4]},
                               {"key": "thesis", "label": "thesis", "thesis": list(th.values())}]})

    # Clearance (Fig. 4.20) and the agreement.
    rate = np.gradient(_ring(cmd, t), t)
    _write_csv(out / "data/clearance_fit.csv", {"time_s": t, "gyro_mean_deg_s": rate + rng.normal(0, 2, t.size),
                                                "model_link_rate_deg_s": np.gradient(_ring(cmd, t, 15.4), t)})
    figures.append({"id": "clearance-fit", "thesis_figure": "4.20", "kind": "time-series",
                    "title": "Model with clearance vs gyro, Step 20°", "file": "data/clearance_fit.csv", "x": xs,
                    "y_label": "link rate (deg/s)",
                    "series": [{"column": "gyro_mean_deg_s", "label": "experiment (mean gyro)"},
                               {"column": "model_link_rate_deg_s", "label": "model with clearance"}]})
    tables.append({"id": "4.3-clearance", "kind": "parameters", "title": "Clearance model (Eq. 4.3)", "unit": "",
                   "row_labels": ["K (N·m/rad^n)", "D (N·m·s/rad)", "Eq. 4.1 agreement"],
                   "columns": [{"key": "ours", "label": "clearshape (fitted)", "ours": [300.0, 0.1, 0.0051]},
                               {"key": "thesis", "label": "thesis (units unstated)",
                                "thesis": [10000.0, 300.0, thesis.CLEARANCE_AGREEMENT_EQ_4_1["position"]]}]})

    # Simulation (Fig. 5.12) and sensitivity.
    shaped = _zvdd(cmd, t)
    _write_csv(out / "data/simulation_step-20.csv",
               {"time_s": t, "link_angle_deg_none": _ring(cmd, t), "link_angle_deg_zvdd@link-mode": _ring(shaped, t)})
    figures.append({"id": "simulation-step-20", "thesis_figure": "5.12", "kind": "time-series",
                    "title": "Simulation with clearance, Step 20°: unshaped and shaped",
                    "file": "data/simulation_step-20.csv", "x": xs, "y_label": "link angle (deg)",
                    "series": [{"column": "link_angle_deg_none", "label": "unshaped"},
                               {"column": "link_angle_deg_zvdd@link-mode", "label": "zvdd (link-mode)"}]})
    ratio = np.linspace(0, 2.5, 251)
    _write_csv(out / "data/sensitivity.csv", {"frequency_ratio": ratio,
                                              "residual_zvdd@link-mode": np.abs(np.cos(math.pi * ratio / 2)) ** 3})
    figures.append({"id": "shaper-sensitivity", "thesis_figure": None, "kind": "sensitivity",
                    "title": "Shaper sensitivity", "file": "data/sensitivity.csv",
                    "x": {"column": "frequency_ratio", "label": "ω / ωm"}, "y_label": "residual vibration V",
                    "series": [{"column": "residual_zvdd@link-mode", "label": "zvdd (link-mode)"}]})

    # Rig tests: Table B.1 and B.6, Figs. 5.9, 5.18, 5.19.
    cols = {"none": [], "zvdd@link-mode": []}
    first = {}
    for k in range(trials):
        noise = rng.normal(0, 0.002, t.size)
        for key, c in (("none", cmd), ("zvdd@link-mode", shaped)):
            y = _ring(c, t, ring=1.0 + 0.05 * k) + noise
            cols[key].append(_md(t, y))
            if k == 0:
                first[key] = (c, y)
    _write_csv(out / "data/rig_B.1.csv", {"time_s": t, "command_none": first["none"][0],
                                          "md_signal_none": first["none"][1],
                                          "command_zvdd@link-mode": first["zvdd@link-mode"][0],
                                          "md_signal_zvdd@link-mode": first["zvdd@link-mode"][1]})
    u = [c[0] for c in cols["none"]]
    w = [c[0] for c in cols["zvdd@link-mode"]]
    imp = 100 * (np.mean(u) - np.mean(w)) / np.mean(u)
    b1 = thesis.TABLE_B["B.1"]

    def bootstrap(groups, n=2000):  # as the study does (rig_tests.hpp): each group resampled on its own
        stats = []
        for _ in range(n):
            m = [float(np.mean(rng.choice(g, len(g)))) for g in groups]
            v = 100 * (1 - m[1] / m[0])
            stats.append(v - 100 * (1 - m[3] / m[2]) if len(m) == 4 else v)
        return [float(np.percentile(stats, 2.5)), float(np.percentile(stats, 97.5))]

    ci = bootstrap([u, w])
    printed = {"thesis_printed": [f"{v:.3f}" for v in b1["zvdd"]], "thesis_mean_printed": f"{b1['mean']['zvdd']:.3f}"}
    tables.append({"id": "B.1", "kind": "mean-deviation", "title": "Mean deviations, step input 20°", "unit": "deg",
                   "row_labels": [str(i + 1) for i in range(trials)],
                   "columns": [{"key": "none", "label": "without IS", "ours": u, "ours_mean": float(np.mean(u)),
                                "ours_std": float(np.std(u, ddof=1)), "thesis": b1["unshaped"],
                                "thesis_mean": b1["mean"]["unshaped"],
                                "thesis_printed": [f"{v:.3f}" for v in b1["unshaped"]],
                                "thesis_mean_printed": f"{b1['mean']['unshaped']:.3f}"},
                               {"key": "zvdd@link-mode", "label": "with IS (ZVDD, link mode)", "ours": w,
                                "ours_mean": float(np.mean(w)), "ours_std": float(np.std(w, ddof=1)),
                                "thesis": b1["zvdd"], "thesis_mean": b1["mean"]["zvdd"],
                                "improvement_percent": float(imp), "improvement_ci95_percent": ci,
                                "improvement_significant": not ci[0] <= 0 <= ci[1],
                                "thesis_improvement_percent": thesis.TABLE_B_6["B.1"],
                                "thesis_improvement_recomputed_percent":
                                    100 * (1 - b1["mean"]["zvdd"] / b1["mean"]["unshaped"]),
                                "improvement_difference_ci95_percent": bootstrap([u, w, b1["unshaped"], b1["zvdd"]]),
                                "thesis_improvement_printed": f"{thesis.TABLE_B_6['B.1']:g}", **printed}]})
    tables.append({"id": "B.6", "kind": "improvement", "title": "Mean of the improvements (ZVDD), %", "unit": "%",
                   "row_labels": ["Step 20°"],
                   "columns": [{"key": "improvement", "label": "improvement", "ours": [float(imp)],
                                "thesis": [thesis.TABLE_B_6["B.1"]], "improvement_ci95_percent": [ci],
                                "thesis_printed": [f"{thesis.TABLE_B_6['B.1']:g}"]}]})
    md0, m0, s0 = cols["none"][0]
    figures += [
        {"id": "rig-B.1", "thesis_figure": "5.19", "kind": "time-series", "title": "Rig trial 1, Step 20°: link angle",
         "file": "data/rig_B.1.csv", "x": xs, "y_label": "link angle (deg)",
         "series": [{"column": "md_signal_none", "label": "without IS"},
                    {"column": "md_signal_zvdd@link-mode", "label": "with IS (ZVDD, link mode)"}],
         "mean_deviation": {key: {"steady_mean": v[0][1], "start_time_s": v[0][2], "mean_deviation": v[0][0]}
                            for key, v in cols.items()}},
        {"id": "rig-inputs-B.1", "thesis_figure": "5.18", "kind": "time-series",
         "title": "Unshaped and shaped commands, Step 20°", "file": "data/rig_B.1.csv", "x": xs,
         "y_label": "command (deg)", "series": [{"column": "command_none", "label": "without IS"},
                                                {"column": "command_zvdd@link-mode", "label": "with IS (ZVDD)"}]},
        {"id": "mean-deviation-illustration", "thesis_figure": "5.9", "kind": "mean-deviation",
         "title": "Eq. 5.1 on trial 1 of the Step 20° without shaping", "file": "data/rig_B.1.csv", "x": xs,
         "y_label": "link angle (deg)", "series": [{"column": "md_signal_none", "label": "response"}],
         "steady_mean": m0, "start_time_s": s0},
    ]

    results = {
        "schema_version": 2, "results_schema_version": 2, "clearshape_version": "fixture", "synthetic": True,
        "study": {"name": "synthetic-fixture", "title": "Synthetic fixture (made-up numbers)", "mode": "position",
                  "quick": True, "seed": seed, "rig": "synthetic fixture (closed-form responses, not a simulation)"},
        "rig": {"kind": "simulated-thesis", "description": "synthetic fixture",
                "summary": "a synthetic fixture standing for clearshape's simulated thesis rig (made-up numbers).",
                "calibrated_to_thesis": True, "scored_against_thesis": True},
        "protocol": {"rig_tests": {"tables": [{"id": "B.1", "columns": [
            {"key": "none"}, {"key": "zvdd@link-mode", "thesis_improvement": thesis.TABLE_B_6["B.1"]}]}]}},
        "units": {"time": "s", "mean_deviation": "deg"},
        "ambiguities": [{"id": "which-mode", "question": "Which mode are the shapers designed for?",
                         "settled": "Both, side by side.", "why": "The position-mode drive model has ζ ≈ 1."}],
        "sections": {"identification": {"selected_input": "step-20",
                                        "drive_mode": {"natural_frequency_rad_s": 1 / ours[3], "damping_ratio": ours[2]}}},
        "tables": tables, "figures_index": "figures.json",
    }
    (out / "results.json").write_text(json.dumps(results, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
    (out / "figures.json").write_text(json.dumps({"schema_version": 2, "figures": figures}, indent=2,
                                                 ensure_ascii=False) + "\n", encoding="utf-8")
    (out / "tables.md").write_text("# synthetic fixture — tables\n\nMade-up numbers; see results.json.\n",
                                   encoding="utf-8")
    return out


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description="Writes a synthetic clearshape study output folder.")
    p.add_argument("out")
    p.add_argument("--trials", type=int, default=3)
    a = p.parse_args(argv)
    print(write_fixture(Path(a.out), a.trials))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
