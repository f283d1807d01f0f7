"""What the CLI's recommend, shape --model and simulate --config read and compute, from Python
(rig/config.hpp, study/clearance_model_json.hpp, study/recommend_report.hpp): each against the
CLI on the same input — the same C++, so the numbers are equal bit for bit."""
import json
import os

import numpy as np
import pytest

import clearshape
from conftest import deg_to_rad, rad_to_deg, read_csv

GOLDEN = os.environ.get("CLEARSHAPE_GOLDEN_DIR", os.path.join(os.path.dirname(__file__), "..", "golden"))
SPECTRUM = os.path.join(GOLDEN, "recommend_one_mode.csv")

# A `fit-clearance --json` document: the thesis P3UZ position drive, 0.5° play, friction.
FIT = {"command": "fit-clearance", "mode": "position", "link_inertia_kg_m2": 0.005,
       "parameters": {"stiffness": {"value": 45.158834415041305}, "damping": {"value": 0.12355192243621643},
                      "play": {"value": 0.5}, "exponent": {"value": 1.0},
                      "coulomb": {"value": 0.001}, "viscous": {"value": 0.0002}},
       "drive": {"model": "P3UZ", "parameters": {"Kp": {"value": 0.9959}, "Tz": {"value": 0.0042},
                                                 "Zeta": {"value": 0.9968}, "Tw": {"value": 0.0102},
                                                 "Tp3": {"value": 0.0034}}}}

RIG_TOML = """[joint]
clearance_deg = 0.3
[contact]
model = "hunt-crossley"
stiffness = 500.0
[run]
seed = 7
duration_s = 1.0
"""


@pytest.fixture(scope="module")
def fit_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("model") / "fit.json"
    path.write_text(json.dumps(FIT))
    return path


def test_recommend_from_the_spectrum_is_the_clis_document(cli_json):
    ref = cli_json("recommend", "--data", SPECTRUM, "--column", "gyro_deg_s", "--max-delay-s", 0.1)
    got = clearshape.recommend([SPECTRUM], column="gyro_deg_s", max_delay_s=0.1)
    assert got == ref
    assert got["recommendation"]["name"] and got["model"] is None


def test_recommend_on_a_model_is_the_clis_document(cli_json, fit_file):
    ref = cli_json("recommend", "--data", SPECTRUM, "--column", "gyro_deg_s", "--model", fit_file,
                   "--move", "step", "--amplitude", 20, "--start-s", 0.2, "--move-duration-s", 2)
    got = clearshape.recommend([SPECTRUM], column="gyro_deg_s", model=str(fit_file), move="step",
                               move_parameters={"amplitude": 20, "start_s": 0.2}, move_duration_s=2)
    assert got == ref
    unshaped = got["model"]["unshaped_md"]
    assert unshaped > 0.1  # a 20° step with 0.5° play rings
    assert got["recommendation"]["predicted_md"] < unshaped


def test_clearance_aware_candidate_on_the_update_grid_is_the_clis(cli_json, fit_file):
    args = ["--data", SPECTRUM, "--column", "gyro_deg_s", "--model", fit_file, "--move", "step",
            "--amplitude", 20, "--start-s", 0.2, "--move-duration-s", 2, "--clearance-aware", "--grid-hz", 30]
    ref = cli_json("recommend", *args)
    got = clearshape.recommend([SPECTRUM], column="gyro_deg_s", model=str(fit_file),
                               move_parameters={"amplitude": 20, "start_s": 0.2}, move_duration_s=2,
                               clearance_aware=True, grid_hz=30)
    for doc in (got, ref):  # the design's wall-clock time is the only number that may differ
        doc["candidates"][-1].pop("design_time_s")
    assert got == ref
    ca = got["candidates"][-1]
    assert ca["name"] == "clearance-aware" and ca["duration_s"] <= ca["max_duration_s"]
    times = [i["time_s"] for i in ca["impulses"]]  # on the 30 Hz grid: whole updates
    np.testing.assert_allclose(np.array(times) * 30, np.round(np.array(times) * 30), atol=1e-9)


def test_recommend_errors_are_the_clis(cli, fit_file):
    stderr = cli("recommend", "--data", SPECTRUM, "--column", "gyro_deg_s", "--model", fit_file, "--move", "step",
                 "--amplitude", 20, expect=2)
    with pytest.raises(ValueError) as e:
        clearshape.recommend([SPECTRUM], column="gyro_deg_s", model=str(fit_file), move_parameters={"amplitude": 20})
    assert str(e.value) in stderr  # a move at t = 0, where the model starts at rest
    with pytest.raises(ValueError, match="initial_play_fraction"):
        clearshape.recommend([SPECTRUM], column="gyro_deg_s", model=str(fit_file),
                             move_parameters={"amplitude": 20, "start_s": 0.2}, initial_play=2)


def test_read_clearance_model_gives_the_files_numbers(fit_file):
    m = clearshape.read_clearance_model(str(fit_file))
    p = FIT["parameters"]
    assert m["mode"] == "position" and m["drive_model"] == "P3ZU" and m["contact_law"] == "dashpot"  # P3UZ, canonical
    assert m["drive_parameters"] == {k: v["value"] for k, v in FIT["drive"]["parameters"].items()}
    assert m["stiffness"] == p["stiffness"]["value"] and m["damping"] == p["damping"]["value"]
    assert m["exponent"] == 1.0 and m["play_rad"] == deg_to_rad(0.5)
    assert m["coulomb_n_m"] == 0.001 and m["viscous_n_m_s_per_rad"] == 0.0002
    assert m["link_inertia_kg_m2"] == 0.005 and m["link_frequency_hz"] is None


def test_read_clearance_model_names_the_missing_key(tmp_path):
    bad = json.loads(json.dumps(FIT))
    del bad["parameters"]["stiffness"]
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(bad))
    with pytest.raises(ValueError, match="parameters.stiffness"):
        clearshape.read_clearance_model(str(path))


def test_rig_config_simulates_as_the_cli(cli, tmp_path):
    config = tmp_path / "rig.toml"
    config.write_text(RIG_TOML)
    out = tmp_path / "run.csv"
    cli("simulate", "--config", config, "--signal", "step", "--amplitude", 10, "--start-s", 0.1, "-o", out)
    ref = read_csv(out)
    c = clearshape.load_rig_config(str(config))
    assert (c["seed"], c["duration_s"], c["sensor_noise"]) == (7, 1.0, True)
    truth = c["truth"]
    assert truth.clearance_rad == deg_to_rad(0.3)
    assert truth.contact("position")["model"] == "hunt-crossley" and truth.contact("position")["stiffness"] == 500.0
    _, deg = clearshape.signal("step", amplitude=10, start_s=0.1, duration_s=1.0)
    r = clearshape.simulate(deg_to_rad(deg), 1e-3, "position", truth, duration_s=c["duration_s"], seed=c["seed"])
    for py_name, cli_name in [("link_angle_rad", "link_deg"), ("gyro_rate_rad_s", "gyro_deg_s")]:
        np.testing.assert_array_equal(rad_to_deg(r[py_name]), ref[cli_name], err_msg=py_name)
    from_text = clearshape.rig_truth_from_toml(RIG_TOML)
    assert from_text.clearance_rad == truth.clearance_rad and from_text.contact("speed") == truth.contact("speed")


def test_rig_config_errors_are_the_clis(cli, tmp_path):
    config = tmp_path / "bad.toml"
    config.write_text("[joint]\nclearance_deg = -1\n")
    stderr = cli("simulate", "--config", config, "--signal", "step", expect=2)
    with pytest.raises(ValueError) as e:
        clearshape.load_rig_config(str(config))
    assert str(e.value) in stderr and "bad.toml:2" in str(e.value)
    with pytest.raises(ValueError, match="unknown table"):
        clearshape.rig_truth_from_toml("[jont]\nclearance_deg = 1\n")


THESIS_DRIVE = {"Kp": 0.9959, "Tz": 0.0042, "Zeta": 0.9968, "Tw": 0.0102, "Tp3": 0.0034}  # Eq. 4.2, P3UZ


def test_fit_clearance_is_the_clis_and_recovers_the_simulated_play(cli, cli_json, tmp_path):
    # A noise-free 20° step of the thesis rig with 0.5° play (its contact law: K 45.16, n 1).
    record = tmp_path / "step.csv"
    cli("simulate", "--signal", "step", "--amplitude", 20, "--start-s", 0.2, "--duration", 2.5,
        "--clearance-deg", 0.5, "--no-noise", "-o", record)
    c = clearshape.thesis_truth().contact("position")
    ref = cli_json("fit-clearance", "--model", "P3UZ", *[f"--param={k}={v!r}" for k, v in THESIS_DRIVE.items()],
                   "--data", record, "--command-column", "drive_command_deg", "--gyro-column", "link_deg_s",
                   "--fit", "stiffness", "play", "--exponent", repr(c["exponent"]), "--damping", repr(c["damping"]),
                   "--max-evaluations", 20, "--sensor-low-pass", "none")
    got = clearshape.fit_clearance([str(record)], drive_model="P3UZ", drive_parameters=THESIS_DRIVE,
                                   command_column="drive_command_deg", gyro_column="link_deg_s",
                                   fit=["stiffness", "play"], exponent=c["exponent"], damping=c["damping"],
                                   max_evaluations=20, sensor_low_pass_hz=0)
    assert got == ref
    p = got["parameters"]
    assert p["play"]["value"] == pytest.approx(0.5, rel=0.1)  # the simulated truth (measured 0.518)
    assert p["stiffness"]["value"] == pytest.approx(c["stiffness"], rel=0.05)  # measured 45.6 against 45.16
    assert got["agreement"] < 0.01 < got["start_agreement"]  # Eq. 4.1
    # The document reads back as the model recommend and shape --model use.
    path = tmp_path / "fit.json"
    path.write_text(json.dumps(got))
    m = clearshape.read_clearance_model(str(path))
    assert m["play_rad"] == deg_to_rad(p["play"]["value"]) and m["stiffness"] == p["stiffness"]["value"]


def test_fit_clearance_errors_name_the_input(tmp_path):
    with pytest.raises(ValueError, match="drive"):
        clearshape.fit_clearance([str(tmp_path / "none.csv")])
    with pytest.raises(ValueError, match="none.csv"):
        clearshape.fit_clearance([str(tmp_path / "none.csv")], drive_model="P3UZ", drive_parameters=THESIS_DRIVE)


STUDIES = os.path.join(os.path.dirname(__file__), "..", "..", "studies")


def test_study_writes_the_clis_files_and_summary(cli, tmp_path):
    protocol = os.path.join(STUDIES, "thesis-position.toml")
    ref = json.loads(cli("study", protocol, "--quick", "--json", "--threads", 2, "--out", tmp_path / "cli"))
    got = clearshape.study(protocol, str(tmp_path / "py"), quick=True, threads=2)
    for doc in (ref, got):  # wall-clock seconds and the folder are the only differences
        doc.pop("timing"), doc.pop("out_dir")
    assert got == ref
    assert got["study"]["quick"] and got["study"]["name"] == "thesis-position"
    for name in ("results.json", "tables.md", "figures.json"):
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    with pytest.raises(ValueError, match="large-play"):
        clearshape.study(protocol, str(tmp_path / "bad"), quick=True, rig="nope")
    with pytest.raises(ValueError, match="not several"):
        clearshape.study(protocol, str(tmp_path / "bad"), rig="thesis", rig_config="x.toml")
    assert not (tmp_path / "bad").exists()
