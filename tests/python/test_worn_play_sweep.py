"""scripts/worn-play-sweep.py: each design's improvement from each start place is the one a direct
`clearshape simulate` gives, the study's trial numbers are carried over, and a play outside the
worn rig's range is refused naming --plays. The study is a small stand-in results.json (the
script reuses a finished study), so the test costs the noise-free simulations only."""
import csv
import json
import os
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCRIPT = os.path.join(ROOT, "scripts", "worn-play-sweep.py")


def stand_in_study(folder):
    """A finished study at 1° with a ZVDD-like shaper and one step input."""
    os.makedirs(os.path.join(folder, "play-1", "study"))
    results = {
        "protocol": {"record_s": 2.0,
                     "inputs": [{"name": "step-10", "label": "Step 10°", "type": "step", "amplitude_deg": 10.0,
                                 "start_s": 0.5}]},
        "sections": {"shapers": [{"key": "zvdd@link-mode",
                                  "impulses": [{"time_s": 0.0, "amplitude": 0.5},
                                               {"time_s": 1.0 / 30.0, "amplitude": 0.5}]}]},
        "tables": [{"id": "B.6", "columns": [{"ours": [43.5]}]}],
    }
    with open(os.path.join(folder, "play-1", "study", "results.json"), "w") as f:
        json.dump(results, f)


def run_sweep(out, *args):
    exe = os.environ["CLEARSHAPE_CLI"]
    return subprocess.run([sys.executable, SCRIPT, "--exe", exe, "--out", str(out), *args],
                          capture_output=True, text=True, cwd=ROOT)


def test_each_start_place_is_a_direct_simulation(tmp_path, cli_json):
    stand_in_study(tmp_path)
    r = run_sweep(tmp_path, "--plays", "1", "--jobs", "2")
    assert r.returncode == 0, r.stderr
    with open(tmp_path / "sweep.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert {row["start_fraction"] for row in rows} == {"-1", "-0.5", "0", "0.5", "1"}
    config = str(tmp_path / "play-1" / "rig.toml")
    for row in rows[::2]:
        base = ["simulate", "--config", config, "--no-noise", "--command-path", "realtime", "--initial-play", row["start_fraction"],
                "--duration", "2", "--signal", "step", "--amplitude", "10", "--start-s", "0.5"]
        unshaped = cli_json(*base)["mean_deviation_eq_5_1"]["link_angle_deg"]["mean_deviation"]
        shaped = cli_json(*base, "--shaper", "custom", "--shaper-impulses",
                          "0:0.5,0.03333333333333333:0.5")["mean_deviation_eq_5_1"]["link_angle_deg"]["mean_deviation"]
        assert float(row["md_unshaped_deg"]) == pytest.approx(unshaped, rel=1e-5)
        assert float(row["md_shaped_deg"]) == pytest.approx(shaped, rel=1e-5)
    table = (tmp_path / "sweep.md").read_text()
    worst = min(float(row["improvement_percent"]) for row in rows)
    assert f"| zvdd@link-mode | 43.5 % / {worst:.1f} % |" in table


def test_a_play_outside_the_worn_rig_is_refused(tmp_path):
    r = run_sweep(tmp_path, "--plays", "3")
    assert r.returncode == 2
    assert "--plays" in r.stderr and "[0.5, 2]" in r.stderr


def test_an_update_phase_starts_each_move_that_much_later(tmp_path, cli_json):
    stand_in_study(tmp_path)
    r = run_sweep(tmp_path, "--plays", "1", "--jobs", "2", "--update-phase-ms", "8")
    assert r.returncode == 0, r.stderr
    with open(tmp_path / "sweep.csv", newline="") as f:
        row = next(row for row in csv.DictReader(f) if row["start_fraction"] == "0")
    config = str(tmp_path / "play-1" / "rig.toml")
    base = ["simulate", "--config", config, "--no-noise", "--command-path", "realtime", "--initial-play", "0",
            "--duration", "2", "--signal", "step", "--amplitude", "10", "--start-s", "0.508"]
    unshaped = cli_json(*base)["mean_deviation_eq_5_1"]["link_angle_deg"]["mean_deviation"]
    assert float(row["md_unshaped_deg"]) == pytest.approx(unshaped, rel=1e-5)
    assert "8 ms after an update instant" in (tmp_path / "sweep.md").read_text()
    # one update period or more is no phase
    r = run_sweep(tmp_path, "--plays", "1", "--update-phase-ms", "40")
    assert r.returncode == 2 and "--update-phase-ms" in r.stderr and "33.33" in r.stderr
