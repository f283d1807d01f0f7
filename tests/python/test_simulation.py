"""The simulator and the Eq. 5.1 / 4.1 metrics against `clearshape simulate` (same truth, same
command: the same C++ runs, so the arrays are bit-identical) and an independent NumPy Eq. 4.1."""
import json

import numpy as np
import pytest

import clearshape
from conftest import deg_to_rad, rad_to_deg, read_csv


@pytest.fixture(scope="module")
def cli_run(cli, tmp_path_factory):
    out = tmp_path_factory.mktemp("sim") / "run.csv"
    cli("simulate", "--mode", "position", "--signal", "step", "--amplitude", 20, "--duration", 1.5,
        "--shaper", "zvd", "--shaper-frequency-hz", 3.32, "--shaper-zeta", 0.288, "--clearance-deg", 1.0, "-o", out)
    return read_csv(out), json.loads(out.with_suffix(".json").read_text())


def python_run():
    _, deg = clearshape.signal("step", amplitude=20, duration_s=1.5)
    shaped = clearshape.shape(clearshape.design("zvd", frequency_hz=3.32, zeta=0.288), deg, 1e-3, extend=False)
    truth = clearshape.thesis_truth()
    truth.clearance_rad = float(deg_to_rad(1.0))
    return clearshape.simulate(deg_to_rad(shaped), 1e-3, "position", truth, duration_s=1.5)


def test_simulate_is_bit_identical_to_the_cli(cli_run):
    ref, _ = cli_run
    r = python_run()
    np.testing.assert_array_equal(r["time_s"], ref["time_s"])
    for py_name, cli_name in [("link_angle_rad", "link_deg"), ("link_rate_rad_s", "link_deg_s"),
                              ("motor_angle_rad", "motor_deg"), ("gyro_rate_rad_s", "gyro_deg_s"),
                              ("encoder_angle_rad", "encoder_deg")]:
        np.testing.assert_array_equal(rad_to_deg(r[py_name]), ref[cli_name], err_msg=py_name)
    np.testing.assert_array_equal(r["contact_torque_n_m"], ref["contact_torque_n_m"])
    assert r["events"] > 0 and not r["rigid"]


def test_mean_deviation_eq_5_1_is_the_clis(cli_run):
    ref, doc = cli_run
    md = clearshape.mean_deviation(ref["link_deg_s"], 1e-3)
    expect = doc["summary"]["mean_deviation_eq_5_1"]["link_rate_deg_s"]
    assert md["mean_deviation"] == expect["mean_deviation"]
    assert md["start_time_s"] == expect["start_s"]
    assert md["steady_mean"] == expect["steady_mean"]


def test_consistency_eq_4_1_against_numpy():
    rng = np.random.default_rng(3)
    base = np.sin(np.linspace(0, 3, 400))
    runs = np.array([base + 0.01 * rng.standard_normal(400) for _ in range(5)])
    r = clearshape.consistency(runs)
    m = runs.mean(axis=0)
    e = np.sqrt(((m - runs) ** 2).mean(axis=1)) / (m.max() - m.min())  # Eq. 4.1
    np.testing.assert_allclose(r["errors"], e, rtol=1e-12)
    assert r["mean_error"] == pytest.approx(e.mean(), rel=1e-12)
    with pytest.raises(ValueError, match="2"):
        clearshape.consistency(runs[:1])


def test_improvement_and_delay():
    assert clearshape.improvement_percent(2.0, 0.5) == 75.0
    with pytest.raises(ValueError):
        clearshape.improvement_percent(0.0, 1.0)
    t = np.arange(0, 1, 1e-3)
    assert clearshape.shaping_delay_s(t, np.maximum(t - 0.1, 0), 1e-3) == pytest.approx(0.1, abs=1e-9)


def test_rig_run_draws_the_variation():
    _, deg = clearshape.signal("step", amplitude=20, duration_s=0.5)
    truth = clearshape.thesis_truth()
    v = truth.variation
    assert v["position_gain_rel_sigma"] > 0  # the calibrated rig varies from run to run
    a = clearshape.simulate_rig(deg, 1e-3, "position", truth, duration_s=0.5, seed=1)
    b = clearshape.simulate_rig(deg, 1e-3, "position", truth, duration_s=0.5, seed=1)
    c = clearshape.simulate_rig(deg, 1e-3, "position", truth, duration_s=0.5, seed=2)
    np.testing.assert_array_equal(a["link_rate_deg_s"], b["link_rate_deg_s"])  # seeded
    assert not np.array_equal(a["link_rate_deg_s"], c["link_rate_deg_s"])
    with pytest.raises(ValueError, match="flank_damping_rel_sigma"):
        truth.variation = {"flank_damping_rel_sigma": 5.0}
    with pytest.raises(ValueError, match="not known"):
        truth.variation = {"gain": 0.1}


def test_truth_fields_round_trip():
    t = clearshape.thesis_truth()
    assert t.clearance_rad == pytest.approx(float(deg_to_rad(0.032)), rel=1e-3)
    t.set_contact("speed", stiffness=100.0, damping=2.0)
    c = t.contact("speed")
    assert (c["stiffness"], c["damping"]) == (100.0, 2.0)
    with pytest.raises(ValueError):
        t.set_contact("speed", stiffness=-1.0)


def test_large_play_truth_is_the_clis(cli, tmp_path):
    assert {"thesis", "large-play", "uncalibrated"} <= set(clearshape.truth_names())
    out = tmp_path / "lp.csv"
    cli("simulate", "--rig", "large-play", "--signal", "step", "--amplitude", 10, "--duration", 1.0, "-o", out)
    ref = read_csv(out)
    _, deg = clearshape.signal("step", amplitude=10, duration_s=1.0)
    r = clearshape.simulate(deg_to_rad(deg), 1e-3, "position", clearshape.truth("large-play"), duration_s=1.0)
    np.testing.assert_array_equal(rad_to_deg(r["link_angle_rad"]), ref["link_deg"])
    np.testing.assert_array_equal(r["contact_torque_n_m"], ref["contact_torque_n_m"])
    with pytest.raises(ValueError, match="large-play"):
        clearshape.truth("huge-play")


@pytest.mark.parametrize("truth,mode,amplitude", [("thesis", "position", 20.0), ("large-play", "speed", 1.5)])
def test_simulate_rig_is_the_cpp_run(tmp_path, truth, mode, amplitude):
    """simulate_rig against a small C++ program running the same SimRig (reference_rig_run.cpp)."""
    import os
    import subprocess

    exe = os.environ.get("CLEARSHAPE_RIG_REFERENCE")
    if not exe:
        pytest.fail("CLEARSHAPE_RIG_REFERENCE is not set (ctest sets it)")
    r = subprocess.run([exe, truth, mode, str(amplitude), "0.1", "1.0", "42"], capture_output=True, text=True,
                       check=True)
    (tmp_path / "ref.csv").write_text(r.stdout)
    ref = read_csv(tmp_path / "ref.csv")
    _, u = clearshape.signal("step", amplitude=amplitude, start_s=0.1, duration_s=1.0)
    py = clearshape.simulate_rig(u, 1e-3, mode, clearshape.truth(truth), duration_s=1.0, seed=42)
    for name in ("time_s", "command_applied", "motor_angle_deg", "link_rate_deg_s"):
        np.testing.assert_array_equal(py[name], ref[name], err_msg=name)
    assert np.ptp(py["link_rate_deg_s"]) > 0
