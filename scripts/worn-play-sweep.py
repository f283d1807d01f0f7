#!/usr/bin/env python3
"""The worn coupling across its play (docs/worn-coupling.md, issue 19).

For each total play (default 0.5, 1 and 2 deg) it runs the worn-coupling study with a rig
configuration that sets the play, then scores each design the study made (ZVDD and EI at the
link mode, the clearance-aware design from the fitted model) two ways:
  - through the sensors: the study's own 10-trial improvements (Tables B.6*);
  - noise-free on the rig truth: `clearshape simulate --rig worn-coupling --no-noise` from each
    start place -1, -1/2, 0, 1/2, 1 of the half play, the worst start's improvement.
Writes OUT/sweep.csv (one row per play x design x move x start) and OUT/sweep.md (the tables).
A finished study is reused (OUT/play-<p>/study/results.json); --fresh runs it again.

usage: scripts/worn-play-sweep.py [--exe build/bin/clearshape] [--out out/worn-play-sweep]
                                  [--plays 0.5,1,2] [--jobs 2] [--fresh] [--command-path realtime]
                                  [--update-phase-ms 0]
--update-phase-ms P starts every move of the noise-free check P ms after an update instant of the
drive's 30 Hz clock (the study's rig starts them on one): the phase a controller may meet.
"""
import argparse
import concurrent.futures
import csv
import json
import os
import subprocess
import sys
import tempfile

UPDATE_PERIOD_MS = 1000.0 / 30.0  # the position drive's pulse update (thesis §3.2)

STARTS = (-1.0, -0.5, 0.0, 0.5, 1.0)
DESIGNS = (("zvdd@link-mode", "B.6"), ("ei@link-mode", "B.6-ei"), ("clearance-aware", "B.6-clearance-aware"))
# A rig configuration starts from the calibrated thesis rig (its soft linear flank is the worn
# coupling's): the play and the worn coupling's bearing friction (rig/worn_coupling.hpp) are set.
RIG_CONFIG = "[joint]\nclearance_deg = {play}\nfriction_coulomb_n_m = 0.01\nfriction_viscous_n_m_s_per_rad = 1e-3\n"


def atomic_write(path, text):
    """Writes text to path through a temporary file in the same folder and a rename."""
    folder = os.path.dirname(path) or "."
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=".incomplete.", suffix=os.path.basename(path))
    with os.fdopen(fd, "w", encoding="utf-8") as f:
        f.write(text)
    os.chmod(tmp, 0o644)
    os.replace(tmp, path)


def run_study(exe, play, folder, fresh):
    """The study at one play; returns its results.json (reused unless fresh)."""
    os.makedirs(folder, exist_ok=True)
    config = os.path.join(folder, "rig.toml")
    atomic_write(config, RIG_CONFIG.format(play=play))
    out = os.path.join(folder, "study")
    results = os.path.join(out, "results.json")
    if fresh or not os.path.exists(results):
        print(f"worn-play-sweep: study at {play} deg of play (about 1.5 min) ...", file=sys.stderr, flush=True)
        cmd = [exe, "study", "studies/worn-coupling-position.toml", "--rig-config", config, "--out", out]
        if fresh:
            cmd.append("--fresh")
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    with open(results, encoding="utf-8") as f:
        return config, json.load(f)


def impulse(i):
    """(time_s, amplitude) of one impulse of results.json: schema 2 names, or schema 1's t/a."""
    return (i["time_s"], i["amplitude"]) if "time_s" in i else (i["t"], i["a"])


def shapers_of(results):
    """{design key: "t:a,..."} for the designs the study made."""
    out = {}
    for s in results["sections"].get("shapers", []):
        out[s["key"]] = ",".join(f"{i['time_s']!r}:{i['amplitude']!r}" for i in s["impulses"])
    ca = results["sections"].get("clearance_aware", {})
    if ca.get("impulses"):
        out["clearance-aware"] = ",".join(f"{t!r}:{a!r}" for t, a in map(impulse, ca["impulses"]))
    return out


def signal_args(inp):
    """simulate's options for one protocol input (steps and double steps)."""
    args = ["--amplitude", repr(inp["amplitude_deg"]), "--start-s", repr(inp["start_s"])]
    if inp["type"] == "double-step":
        args = ["--signal", "double-step", *args, "--second-amplitude", repr(inp["second_amplitude_deg"]),
                "--second-start-s", repr(inp["second_start_s"])]
    elif inp["type"] == "step":
        args = ["--signal", "step", *args]
        if inp.get("rise_s"):
            args += ["--rise-s", repr(inp["rise_s"])]
    else:
        return None
    return args


def delayed(inp, phase_ms):
    """The input with its move(s) started phase_ms later."""
    out = dict(inp)
    for key in ("start_s", "second_start_s"):
        if key in out:
            out[key] = out[key] + phase_ms / 1000.0
    return out


def simulate_md(exe, config, inp, start, impulses, duration_s, command_path):
    """Eq. 5.1 of the link angle, noise-free, from one start place (deg)."""
    cmd = [exe, "simulate", "--config", config, "--no-noise", "--json", "--command-path", command_path,
           "--initial-play", repr(start), "--duration", repr(duration_s), *signal_args(inp)]
    if impulses:
        cmd += ["--shaper", "custom", "--shaper-impulses", impulses]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return json.loads(out)["mean_deviation_eq_5_1"]["link_angle_deg"]["mean_deviation"]


def study_improvements(results, table_id):
    for t in results["tables"]:
        if t["id"] == table_id:
            return t["columns"][0]["ours"]
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--exe", default="build/bin/clearshape")
    ap.add_argument("--out", default="out/worn-play-sweep")
    ap.add_argument("--plays", default="0.5,1,2", help="total plays (deg), comma-separated, each in [0.5, 2]")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--fresh", action="store_true", help="run every study again")
    ap.add_argument("--command-path", choices=("realtime", "offline"), default="realtime",
                    help="the noise-free check's pulse path: realtime (the study rig's loop, default) or offline")
    ap.add_argument("--update-phase-ms", type=float, default=0.0,
                    help=f"start the noise-free check's moves this long after an update instant, [0, {UPDATE_PERIOD_MS:.4g})")
    a = ap.parse_args()
    try:
        plays = [float(p) for p in a.plays.split(",")]
    except ValueError:
        ap.error(f"--plays: '{a.plays}' is not a comma-separated list of numbers (deg, each in [0.5, 2])")
    if any(not 0.5 <= p <= 2.0 for p in plays):
        ap.error(f"--plays: {a.plays}: each play must be in [0.5, 2] deg (the worn-coupling rig's range)")
    if not 0.0 <= a.update_phase_ms < UPDATE_PERIOD_MS:
        ap.error(f"--update-phase-ms: {a.update_phase_ms:g} is outside [0, {UPDATE_PERIOD_MS:.4g}) ms (one update period)")
    os.makedirs(a.out, exist_ok=True)
    rows, md_lines = [], []
    for play in plays:
        config, results = run_study(a.exe, play, os.path.join(a.out, f"play-{play:g}"), a.fresh)
        shapers = shapers_of(results)
        inputs = [i for i in results["protocol"]["inputs"] if signal_args(i) is not None]
        duration_s = results["protocol"]["record_s"]
        jobs = {}
        with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as pool:
            for inp in inputs:
                for start in STARTS:
                    for design in ("unshaped", *[d for d, _ in DESIGNS if d in shapers]):
                        imp = shapers.get(design, "")
                        jobs[(inp["name"], start, design)] = pool.submit(
                            simulate_md, a.exe, config, delayed(inp, a.update_phase_ms), start, imp, duration_s,
                            a.command_path)
        md = {k: f.result() for k, f in jobs.items()}
        md_lines += [f"## {play:g}° of play", "",
                     "Improvement of Eq. 5.1 (link angle) over unshaped: the study's 10 trials through the "
                     f"sensors / noise-free on the rig truth ({a.command_path} pulse path, moves {a.update_phase_ms:g} ms after an "
                     "update instant), worst of the five "
                     "start places.", "",
                     "| design | " + " | ".join(i["label"] for i in inputs) + " |",
                     "|---" * (len(inputs) + 1) + "|"]
        for design, table in DESIGNS:
            if design not in shapers:
                continue
            trials = study_improvements(results, table) or [None] * len(inputs)
            cells = []
            for k, inp in enumerate(inputs):
                worst = min(100.0 * (1.0 - md[(inp["name"], s, design)] / md[(inp["name"], s, "unshaped")])
                            for s in STARTS)
                for s in STARTS:
                    u, d = md[(inp["name"], s, "unshaped")], md[(inp["name"], s, design)]
                    rows.append([f"{play:g}", design, inp["name"], f"{s:g}", f"{u:.6g}", f"{d:.6g}",
                                 f"{100.0 * (1.0 - d / u):.2f}"])
                trial = "—" if trials[k] is None else f"{trials[k]:.1f} %"
                cells.append(f"{trial} / {worst:.1f} %")
            md_lines.append(f"| {design} | " + " | ".join(cells) + " |")
        md_lines.append("")
    header = ["play_deg", "design", "input", "start_fraction", "md_unshaped_deg", "md_shaped_deg", "improvement_percent"]
    text = ",".join(header) + "\n" + "".join(",".join(r) + "\n" for r in rows)
    atomic_write(os.path.join(a.out, "sweep.csv"), text)
    atomic_write(os.path.join(a.out, "sweep.md"), "# The worn coupling across its play\n\n" + "\n".join(md_lines))
    print("\n".join(md_lines))
    print(f"worn-play-sweep: {a.out}/sweep.md, {a.out}/sweep.csv", file=sys.stderr)


if __name__ == "__main__":
    main()
