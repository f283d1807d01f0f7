"""arm_mode_map (docs/arm.md §7-§8) against `clearshape arm modes --identify --json` and
`--recordings MANIFEST --json` on the same options: the same document, dict for dict (the CLI's
JSON is shortest round-trip, so the numbers are equal to the bit); the recordings it writes are
the CLI's byte for byte and read back as the simulated map; each pose's linearised modes are
arm_modes' at that pose; without play the first mode is identified at the linearised frequency
(eig(M⁻¹K), to 1e-4); bad options are refused naming the argument and its range."""
import filecmp
import runpy
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import clearshape as cs

REPO = Path(__file__).resolve().parents[2]
CLI_KEYS = ("schema_version", "clearshape_version", "arm", "source", "modes", "failures")


def cli_args(grid=None, step_deg=None, sensor=None, excitation=None, ramp_velocity_rad_s=None, max_damping=None,
             play_deg=None, arm=None):
    args = []
    for flag, value in (("--grid", grid), ("--step-deg", step_deg), ("--sensor", sensor),
                        ("--excitation", excitation), ("--ramp-velocity", ramp_velocity_rad_s),
                        ("--max-damping", max_damping), ("--play-deg", play_deg), ("--arm", arm)):
        if value is not None:
            args += [flag, repr(value) if isinstance(value, float) else value]
    return args


def assert_cli_document(py, cli):
    assert set(CLI_KEYS) == set(cli)
    for key in CLI_KEYS:
        assert py[key] == cli[key], key


@pytest.mark.parametrize("kwargs", [
    {"grid": 2},
    {"grid": 2, "play_deg": 0.0, "step_deg": 0.5},
    {"grid": 2, "excitation": "loaded-ramp", "sensor": "gyro", "ramp_velocity_rad_s": 0.03, "max_damping": 0.04},
    {"grid": 2, "excitation": "loaded-ramp", "arm": "vertical-2"},
])
def test_identify_equals_the_cli(cli_json, kwargs):
    py = cs.arm_mode_map(**kwargs)
    assert_cli_document(py, cli_json("arm", "modes", "--identify", *cli_args(**kwargs)))
    assert py["modes"] and len(py["points"]) == 4
    assert [row for p in py["points"] for row in p["modes"]] == py["modes"]
    assert [{"pose_rad": p["pose_rad"], "run": f} for p in py["points"] for f in p["failures"]] == py["failures"]


def test_linearised_modes_beside_each_pose_are_arm_modes():
    for p in cs.arm_mode_map(grid=2, play_deg=0.0)["points"]:
        lin = cs.arm_modes(p["pose_rad"])
        np.testing.assert_array_equal(p["linearised"]["natural_frequency_hz"], lin["natural_frequency_hz"])
        np.testing.assert_array_equal(p["linearised"]["damping_ratio"], lin["damping_ratio"])
        for row in p["modes"]:
            assert row["linear_frequency_hz"] == p["linearised"]["natural_frequency_hz"][row["linear_mode"]]
        # without play the links ring at the linearised modes: the first one identified to 1e-4
        first = [row for row in p["modes"] if row["linear_mode"] == 0]
        assert first and abs(first[0]["relative_frequency_error"]) < 1e-4


def test_own_arm_from_texts_equals_the_cli_on_files(cli_json, tmp_path):
    urdf, toml = cs.arm_text("vertical-2")
    (tmp_path / "arm.urdf").write_text(urdf)
    (tmp_path / "arm.toml").write_text(toml)
    py = cs.arm_mode_map(urdf=urdf, toml=toml, grid=1, excitation="loaded-ramp", play_deg=0.3)
    assert_cli_document(py, cli_json("arm", "modes", "--identify", "--urdf", tmp_path / "arm.urdf", "--config",
                                     tmp_path / "arm.toml", *cli_args(grid=1, excitation="loaded-ramp", play_deg=0.3)))


def test_recordings_equal_the_cli_and_the_simulated_map(cli, cli_json, tmp_path):
    options = {"grid": 2, "excitation": "loaded-ramp"}
    simulated = cs.arm_mode_map(write_recordings=str(tmp_path / "py"), **options)
    cli("arm", "modes", "--identify", *cli_args(**options), "--write-recordings", tmp_path / "cli")
    files = sorted(p.name for p in (tmp_path / "py").iterdir())
    assert "manifest.toml" in files and len(files) == 5  # four poses' ramps and the manifest
    match, mismatch, errors = filecmp.cmpfiles(tmp_path / "py", tmp_path / "cli", files, shallow=False)
    assert (mismatch, errors) == ([], []), (mismatch, errors)
    manifest = str(tmp_path / "py" / "manifest.toml")
    for sensor in ("links", "gyro"):
        recorded = cs.arm_mode_map(recordings=manifest, sensor=sensor)
        assert_cli_document(recorded, cli_json("arm", "modes", "--recordings", manifest, "--sensor", sensor))
    # the files hold the simulated windows exactly: the same rows as the simulated map
    assert simulated["modes"] and not simulated["failures"]
    assert cs.arm_mode_map(recordings=manifest)["modes"] == simulated["modes"]


def test_recordings_refusals_are_the_clis(cli, tmp_path):
    cs.arm_mode_map(grid=1, excitation="loaded-ramp", write_recordings=str(tmp_path))
    manifest = str(tmp_path / "manifest.toml")
    stderr = cli("arm", "modes", "--recordings", manifest, "--arm", "vertical-2", expect=2)
    with pytest.raises(ValueError) as e:
        cs.arm_mode_map(arm="vertical-2", recordings=manifest)
    assert "field 'arm'" in str(e.value) and str(e.value) in stderr
    with pytest.raises(ValueError, match="missing.toml"):
        cs.arm_mode_map(recordings=str(tmp_path / "missing.toml"))


@pytest.mark.parametrize("kwargs, named", [
    ({"grid": 0}, r"grid = 0 is out of range; allowed: \[1, 10\]"),
    ({"grid": 11}, r"grid = 11 .*\[1, 10\]"),
    ({"step_deg": 0.0}, r"step_deg = 0 .*\[0.01, 30\]"),
    ({"step_deg": 31.0}, r"step_deg = 31 .*\[0.01, 30\]"),
    ({"ramp_velocity_rad_s": 2.0}, r"ramp_velocity_rad_s = 2 .*\[0.001, 1\]"),
    ({"max_damping": 0.0}, r"max_damping = 0 .*\[0.001, 1\]"),
    ({"play_deg": 11.0}, r"play_deg = 11 .*\[0, 10\]"),
    ({"sensor": "imu"}, "sensor = 'imu'; allowed: links, gyro"),
    ({"excitation": "chirp"}, "excitation = 'chirp'; allowed: step, loaded-ramp"),
    ({"recordings": "m.toml", "grid": 2}, "recordings and grid"),
    ({"recordings": "m.toml", "excitation": "step"}, "recordings and excitation"),
    ({"recordings": "m.toml", "write_recordings": "out"}, "recordings and write_recordings"),
    ({"urdf": "<robot/>"}, "urdf and toml go together"),
    ({"arm": "scara-3"}, "scara-3"),
])
def test_bad_options_are_named(kwargs, named):
    with pytest.raises(ValueError, match=named):
        cs.arm_mode_map(**kwargs)


def test_the_docs_example_runs(tmp_path, monkeypatch, capsys):
    block = subprocess.run([sys.executable, REPO / "scripts" / "doc-block.py", REPO / "docs" / "python.md",
                            "The arm's mode map", "python"], capture_output=True, text=True, check=True).stdout
    (tmp_path / "example.py").write_text(block)
    monkeypatch.chdir(tmp_path)
    runpy.run_path(str(tmp_path / "example.py"))
    assert capsys.readouterr().out.startswith("-1.7333333333333334 -1.7333333333333334 21.453 ± 0.005 Hz +0.22 % "
                                              "from the linearised 21.406 Hz")
    assert (tmp_path / "rec" / "manifest.toml").exists()
