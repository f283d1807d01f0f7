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
shaper impulses (the link starting in the middle of the play). A shaped column that ran the unshaped
command — its design failed (the column's note says why) or the clearance-aware search kept the
identity (no design beat the unshaped command on the fitted model) — is named so, with the reason as
a footnote: its "improvement" is the scatter of ten trials of the same command, and such a column is
never a reach table's best design without that warning; a design worse than unshaped is marked so.

    /usr/bin/python3 scripts/large-play-table.py [--build-dir build] [--no-run] [--write docs/large-play.md]
"""
import argparse
import json
import os
import re
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
    """The impulses the column's trials ran (the first trial's sidecar), None for the unshaped command:
    a column whose design failed ran unshaped (its sidecar's shaper is null)."""
    if key == "none":
        return None
    with open(os.path.join(out, "runs", f"rig__{table}__{key}__r01.json")) as f:
        shaper = json.load(f)["shaper"]
    return shaper["impulses"] if shaper else None


def named(impulses):
    """Impulses with results.json's schema-2 names (time_s, amplitude); schema 1 wrote t/a."""
    return [i if "time_s" in i else {"time_s": i["t"], "amplitude": i["a"]} for i in impulses]


def is_identity(impulses):
    """One impulse of amplitude 1 at t = 0: the shaper passes the command unchanged."""
    return (impulses is not None and len(impulses) == 1 and abs(impulses[0]["time_s"]) < 1e-12
            and abs(impulses[0]["amplitude"] - 1.0) < 1e-12)


def no_shaper_reason(res, column, impulses):
    """Why a shaped column ran the unshaped command (None when it ran a real shaper): the column's own
    note (a failed design), or the clearance-aware search that kept the identity (no design found that
    beat the unshaped command on the fitted model)."""
    if impulses is not None and not is_identity(impulses):
        return None
    if column.get("note"):
        return column["note"]
    ca = res["sections"].get("clearance_aware")
    if column["key"].startswith("clearance-aware") and ca:
        return (f"the search kept the identity: no design beat the unshaped command on the fitted model "
                f"(worst MD {ca['worst_md_deg']:.4f} deg against {ca['worst_unshaped_md_deg']:.4f} unshaped, "
                f"{ca['evaluations']} evaluations, {ca['termination']})")
    return "no shaper designed (the study gives no reason)"


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


def generic(note):
    """A failed design's note without its per-input numbers, so that one footnote serves every input:
    "… for 5 deg … (residual 1.52); …" -> "… for the input's move … ; …"."""
    note = re.sub(r"^identity shaper \(runs unshaped\): ", "", note)
    note = re.sub(r"for [0-9.]+ deg with", "for the input's move with", note)
    return re.sub(r" \(residual [0-9.eE+-]+\)", "", note)


def reach_lines(res, rig, out_dir, notes):
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
        best_col = next((c for c in t["columns"] if c["key"] == h["best_column"]), None)
        best = best_col["label"] if best_col else "—"
        if best_col is not None:
            reason = no_shaper_reason(res, best_col, shaper_of(out_dir, table, best_col["key"]))
            if reason is not None:  # the lowest mean is the unshaped command's: scatter, not a design
                best += f" {notes.get(generic(reason), ('',))[0]} (no shaper: the unshaped command; not a design)"
            elif h["best_mean"] is not None and h["best_mean"] > h["unshaped_mean"]:
                best += " (worse than unshaped: not a candidate)"
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
            notes = {}  # footnote text -> (its mark, the column), for the shaped columns that ran the unshaped command
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
                    reason = None if key == "none" else no_shaper_reason(res, c, imp)
                    if reason is not None:
                        mark = notes.setdefault(generic(reason), (f"[{chr(ord('a') + len(notes))}]", name))[0]
                        name = f"{name} {mark}: none, runs unshaped"
                        improvement += " (same command as unshaped: trial scatter)"
                    elif c["ours_mean"] > base:
                        improvement += " (worse than unshaped)"
                    col = f"tables[id={table}].columns[key={key}]"
                    quotes = [f"{col}.ours_mean:.4f", f"{col}.ours_std:.4f"]
                    quotes += [] if key == "none" else [f"{col}.improvement_percent:.0f"]
                    lines.append(f"| {label} | {name} | {c['ours_mean']:.4f} ± {c['ours_std']:.4f} | {improvement} | "
                                 f"{delay:.3f} | {torque:.2f} | {impacts} |" + marker(out, *quotes))
            if notes:
                lines.append("")
                lines += [f"{mark} {name}: no shaper designed or kept, the column ran the unshaped command; {text}."
                          for text, (mark, name) in notes.items()]
            lines += reach_lines(res, rig, out, notes)
            ca = res["sections"].get("clearance_aware")
            if ca:
                kept = ("the identity (the unshaped command): no design beat unshaped on the fitted model"
                        if is_identity(named(ca["impulses"]))
                        else "impulses " + ", ".join(f"{i['amplitude']:.3f} at {i['time_s']:.3f} s"
                                                     for i in named(ca["impulses"])))
                warn = (" WORSE than unshaped on the fitted model: not a candidate."
                        if ca.get("worse_than_unshaped") else "")
                lines.append(f"\nclearance-aware on the {rig} rig: {kept}; bound {ca['max_duration_s']:.3f} s; "
                             f"worst MD on the fitted model {ca['worst_md_deg']:.4f} deg (unshaped "
                             f"{ca['worst_unshaped_md_deg']:.4f}); {ca['evaluations']} evaluations.{warn}")
            take_up = res["sections"].get("take_up") or {}
            if not take_up:
                lines.append(f"take-up on the {rig} rig: no profile designed for any input (the tables' notes above).")
            for name, tu in take_up.items():
                lines.append(f"take-up for {name} on the {rig} rig: slots "
                             + "/".join(f"{v:.1f}" for v in tu["slot_velocity_deg_s"])
                             + f" deg/s (impulses " + ", ".join(f"{i['amplitude']:.3f}" for i in named(tu["impulses"]))
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
