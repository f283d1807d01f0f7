#!/usr/bin/python3
"""The side-by-side table of docs/large-play.md (issue 12), measured, never typed.

Runs (or reuses the finished runs of) studies/large-play-position.toml on the large-play rig
(out/large-play-position, also run by `make run`) and on the calibrated thesis rig
(`--rig thesis`, out/large-play-position-thesis-rig): 10 trials per column on each rig's SimRig
with its run-to-run variation. From each results.json: the mean Eq. 5.1 MD (link angle, deg) of
the unshaped trials and of ZVDD, EI, SI (from the link mode the study identified on that rig)
and the clearance-aware shaper (designed on the clearance model the study fitted on that rig),
and the take-up profile (designed per input on the same model), the improvement 1 − MD/MD_unshaped
and the added delay (the shaper's last impulse); then the study's own "What a command can reach
here" (each input's 90 % target against the Eq. 5.1 measurement floor of its rest trials). The peak
contact torque and the impact count (contact onsets) are hidden from a rig's sensors: they come
from one nominal, noise-free `clearshape simulate --rig <rig>` of the same input with the same
shaper impulses (the link starting in the middle of the play).

    /usr/bin/python3 scripts/large-play-table.py [--build-dir build] [--no-run] [--write docs/large-play.md]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

RIGS = [("large-play", "out/large-play-position"), ("thesis", "out/large-play-position-thesis-rig")]
COLUMNS = [("none", "unshaped"), ("zvdd@link-mode", "ZVDD"), ("ei@link-mode", "EI"), ("si@link-mode", "SI"),
           ("clearance-aware@clearance-model", "clearance-aware"), ("take-up@clearance-model", "take-up")]
BEGIN, END = "<!-- large-play-table:begin -->", "<!-- large-play-table:end -->"


def marker(out, *quotes):
    """A doc-numbers marker (scripts/check-doc-numbers.py): the row's numbers from results.json, which
    `make run` checks against its own out/large-play-position (the delay and contact columns come from
    the runs' sidecars and `clearshape simulate`, and are not in results.json)."""
    return f" <!-- doc-numbers {os.path.basename(out)} {' '.join(quotes)} -->"


def run_study(exe, rig, out):
    args = [exe, "study", "studies/large-play-position.toml", "--out", out]
    if rig != "large-play":
        args += ["--rig", rig]
    subprocess.run(args, check=True, stdout=subprocess.DEVNULL)


def signal_args(protocol, input_name):
    s = next(x for x in protocol["inputs"] if x["name"] == input_name)
    args = ["--signal", s["type"]]
    for key, flag in [("amplitude_deg", "--amplitude"), ("start_s", "--start-s"), ("rise_s", "--rise-s"),
                      ("rise_shape", "--rise-shape"), ("second_amplitude_deg", "--second-amplitude"),
                      ("second_start_s", "--second-start-s")]:
        if key in s and s[key] not in (None, 0, 0.0):
            args += [flag, str(s[key])]
    return args


def shaper_of(out, table, key):
    if key == "none":
        return None
    with open(os.path.join(out, "runs", f"rig__{table}__{key}__r01.json")) as f:
        return json.load(f)["shaper"]["impulses"]


def contact(exe, rig, sig, impulses, tmp):
    csv = os.path.join(tmp, "run.csv")
    args = [exe, "simulate", "--rig", rig, "--no-noise", "--duration", "5", "-o", csv] + sig
    if impulses:
        args += ["--shaper", "custom", "--shaper-impulses",
                 ",".join(f"{i['time_s']!r}:{i['amplitude']!r}" for i in impulses)]
    subprocess.run(args, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(os.path.join(tmp, "run.json")) as f:
        side = json.load(f)
    onsets = sum(1 for e in side["events_first_1000"] if e["kind"] in ("onset", "impact"))
    return side["summary"]["peak_contact_torque_n_m"], onsets


def reach_lines(res, rig, out_dir):
    """The study's own "What a command can reach here" (results.json table "reach"): each input's
    90 % target (0.1 × the unshaped mean MD) against the measurement floor, Eq. 5.1 on the rest
    trials (rig_tests.floor_trials) over the window the input's trials used."""
    reach = next((x for x in res["tables"] if x["id"] == "reach"), None)
    if reach is None:
        return []
    fl = res["sections"]["measurement_floor"]
    out = [f"\nWhat a command can reach on the {rig} rig (the study report's table; floor = Eq. 5.1 on "
           f"{fl['trials']} rest trials, zero command, over each input's window):\n",
           "| input | unshaped MD (deg) | 90 % target (deg) | measurement floor (deg) | improvement at the floor "
           "| best design | its MD (deg) | verdict |",
           "|---|---|---|---|---|---|---|---|"]
    for table in ("B.3", "B.2", "B.1", "B.4", "B.5"):
        h = reach["headline"].get(table)
        if h is None:
            continue
        label = next(x.get("label", x["name"]) for x in res["protocol"]["inputs"] if x["name"] == h["input"])
        t = next(x for x in res["tables"] if x["id"] == table)
        best = next((c["label"] for c in t["columns"] if c["key"] == h["best_column"]), "—")
        best_md = f"{h['best_mean']:.4f}" if h["best_mean"] is not None else "—"
        path = f"tables[id=reach].headline[{table}]"
        keys = [f"{path}.{k}:{spec}" for k, spec in (("unshaped_mean", ".4f"), ("unshaped_std", ".4f"), ("target", ".4f"),
                                                      ("floor_mean", ".4f"), ("floor_std", ".4f"),
                                                      ("floor_improvement_percent", ".0f"))]
        if h["best_mean"] is not None:
            keys.append(f"{path}.best_mean:.4f")
        out.append(f"| {label} | {h['unshaped_mean']:.4f} ± {h['unshaped_std']:.4f} | {h['target']:.4f} | "
                   f"{h['floor_mean']:.4f} ± {h['floor_std']:.4f} | {h['floor_improvement_percent']:.0f} % | "
                   f"{best} | {best_md} | {h['verdict']} |" + marker(out_dir, *keys))
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build-dir", default="build")
    ap.add_argument("--no-run", action="store_true", help="use the existing results.json files")
    ap.add_argument("--write", help="replace the table between the markers in this Markdown file")
    a = ap.parse_args()
    exe = os.path.join(a.build_dir, "bin", "clearshape")
    lines = []
    with tempfile.TemporaryDirectory() as tmp:
        for rig, out in RIGS:
            if not a.no_run:
                run_study(exe, rig, out)
            with open(os.path.join(out, "results.json")) as f:
                res = json.load(f)
            lines.append(f"**{rig} rig** ({res['rig']['description']}; protocol hash {res['study']['protocol_hash']})\n")
            lines.append("| input | shaper | MD mean ± std (deg) | improvement | added delay (s) | peak contact torque (N·m) | impacts |")
            lines.append("|---|---|---|---|---|---|---|")
            for table in ("B.3", "B.2", "B.1", "B.4", "B.5"):
                t = next(x for x in res["tables"] if x["id"] == table)
                input_name = next(s["input"] for s in res["protocol"]["rig_tests"]["tables"] if s["id"] == table)
                label = next(x.get("label", x["name"]) for x in res["protocol"]["inputs"] if x["name"] == input_name)
                sig = signal_args(res["protocol"], input_name)
                cols = {c["key"]: c for c in t["columns"]}
                base = cols["none"]["ours_mean"]
                for key, name in COLUMNS:
                    c = cols.get(key)
                    if c is None or c.get("ours_mean") is None:
                        lines.append(f"| {label} | {name} | — | | | | |")
                        continue
                    imp = shaper_of(out, table, key)
                    delay = imp[-1]["time_s"] if imp else 0.0
                    torque, impacts = contact(exe, rig, sig, imp, tmp)
                    improvement = "" if key == "none" else f"{100.0 * (1.0 - c['ours_mean'] / base):.0f} %"
                    col = f"tables[id={table}].columns[key={key}]"
                    quotes = [f"{col}.ours_mean:.4f", f"{col}.ours_std:.4f"]
                    quotes += [] if key == "none" else [f"{col}.improvement_percent:.0f"]
                    lines.append(f"| {label} | {name} | {c['ours_mean']:.4f} ± {c['ours_std']:.4f} | {improvement} | "
                                 f"{delay:.3f} | {torque:.2f} | {impacts} |" + marker(out, *quotes))
            lines += reach_lines(res, rig, out)
            ca = res["sections"].get("clearance_aware")
            if ca:
                lines.append(f"\nclearance-aware on the {rig} rig: impulses "
                             + ", ".join(f"{i['a']:.3f} at {i['t']:.3f} s" for i in ca["impulses"])
                             + f"; bound {ca['max_duration_s']:.3f} s; worst MD on the fitted model "
                             f"{ca['worst_md_deg']:.4f} deg (unshaped {ca['worst_unshaped_md_deg']:.4f}); "
                             f"{ca['evaluations']} evaluations.")
            for name, tu in res["sections"].get("take_up", {}).items():
                lines.append(f"take-up for {name} on the {rig} rig: slots "
                             + "/".join(f"{v:.1f}" for v in tu["slot_velocity_deg_s"])
                             + f" deg/s (impulses " + ", ".join(f"{i['a']:.3f}" for i in tu["impulses"])
                             + f"); the link leaves the rear flank at {tu['separation_s']:.4f} s and meets the braking "
                             f"flank at {tu['contact_s']:.4f} s; Coulomb {tu['coulomb_n_m']:.3g} N·m "
                             + (f"(flank keeping would take {tu['flank_keeping_move_time_s']:.3g} s)."
                                if tu.get("flank_keeping_move_time_s") is not None
                                else "(no friction fitted: flank keeping cannot hold the link)."))
            cl = res["sections"]["clearance"]
            lm = res["sections"]["link_mode"]
            lines.append(f"Fitted on this rig: play {cl['play_deg']:.4f} deg, K {cl['stiffness_n_m_per_rad_pow_n']:.4g}, "
                         f"n {cl['exponent']:.3f}, D {cl['damping_n_m_s_per_rad']:.4g}; link mode "
                         f"{lm.get('natural_frequency_hz', float('nan')):.3f} Hz, ζ {lm.get('damping_ratio', float('nan')):.3f}."
                         + marker(out, "sections.clearance.play_deg:.4f") + marker(out, "sections.clearance.exponent:.3f")
                         + marker(out, "sections.link_mode.natural_frequency_hz:.3f", "sections.link_mode.damping_ratio:.3f")
                         + "\n")
    text = "\n".join(lines)
    print(text)
    if a.write:
        with open(a.write) as f:
            doc = f.read()
        if BEGIN not in doc or END not in doc:
            sys.exit(f"{a.write}: markers {BEGIN} … {END} not found")
        head, rest = doc.split(BEGIN, 1)
        _, tail = rest.split(END, 1)
        new = head + BEGIN + "\n" + text + "\n" + END + tail
        tmp_path = a.write + ".tmp"
        with open(tmp_path, "w") as f:
            f.write(new)
        os.replace(tmp_path, a.write)  # atomic


if __name__ == "__main__":
    main()
