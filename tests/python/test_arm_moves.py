"""The arm's commands from Python (docs/arm.md §7): arm_modes against the SciPy golden of
tests/golden/gen_arm_modes.py; arm_move's synchronised move against its limits, the ROS
JointTrajectory JSON it writes, and the shaped command played by simulate_arm."""
import json
import os

import numpy as np
import pytest
import clearshape as cs

LIMITS = np.array([[2.0, 20.0, 400.0], [3.0, 30.0, 600.0]])


def test_modes_match_the_scipy_golden():
    """tests/golden/arm_scara_modes.csv: scipy.linalg.eigh(K, M) on scara-2's closed-form M(q)."""
    golden = np.genfromtxt(os.path.join(os.environ["CLEARSHAPE_GOLDEN_DIR"], "arm_scara_modes.csv"), delimiter=",",
                           names=True)
    for row in golden[::4]:
        modes = cs.arm_modes([0.3, row["q2_rad"]])
        np.testing.assert_allclose(modes["natural_frequency_hz"], [row["f1_hz"], row["f2_hz"]], rtol=1e-9)
        np.testing.assert_allclose(modes["damping_ratio"], [row["zeta1"], row["zeta2"]], rtol=1e-9)
        np.testing.assert_allclose(modes["share"], [[row["share_1_1"], row["share_1_2"]],
                                                    [row["share_2_1"], row["share_2_2"]]], atol=1e-9)
        assert len(modes["dominant_mode"]) == 2


def test_move_keeps_its_limits_and_writes_a_ros_trajectory(tmp_path):
    move = cs.arm_move([0.0, 1.5], [1.2, 0.6], LIMITS, json_path=str(tmp_path / "m.json"),
                       csv_path=str(tmp_path / "m.csv"))
    q, v, a = move["position_rad"], move["velocity_rad_s"], move["acceleration_rad_s2"]
    assert move["joint_names"] == ["shoulder", "elbow"]
    assert (q[-1] == [1.2, 0.6]).all() and (v[-1] == 0).all()
    assert (np.abs(v) <= LIMITS[:, 0] * (1 + 1e-12)).all() and (np.abs(a) <= LIMITS[:, 1] * (1 + 1e-12)).all()
    doc = json.loads((tmp_path / "m.json").read_text())
    assert doc["joint_names"] == ["shoulder", "elbow"] and len(doc["points"]) == len(move["time_s"])
    last = doc["points"][-1]
    assert last["positions"] == [1.2, 0.6]
    t = last["time_from_start"]["sec"] + 1e-9 * last["time_from_start"]["nanosec"]
    assert t == pytest.approx(move["time_s"][-1], abs=1e-9)
    csv = np.loadtxt(tmp_path / "m.csv", delimiter=",", skiprows=1)
    np.testing.assert_array_equal(csv[:, 1:], q)


def test_shaped_command_plays_on_the_arm():
    move = cs.arm_move([0.0, 1.5], [1.2, 0.6], LIMITS, schedule="scheduled", every_mode=True)
    assert len(move["shapers"][0]) == 9  # ZVD at both modes of the end pose
    assert move["time_s"][-1] == pytest.approx(move["move_duration_s"] + move["shapers"][0].duration_s, abs=1e-3)
    np.testing.assert_allclose(move["commands"][0], move["position_rad"][:, 0] * 50 * 180 / np.pi, rtol=1e-12)
    run = cs.simulate_arm(move["commands"], 1e-3, duration_s=move["time_s"][-1] + 0.3)
    np.testing.assert_allclose(run["output_angle_rad"][-1], [1.2, 0.6], atol=1e-6)  # the drives reach the targets
    with pytest.raises(ValueError, match="allowed: unshaped, fixed, scheduled"):
        cs.arm_move([0, 0], [1, 1], LIMITS, schedule="always")
    with pytest.raises(ValueError, match="2 × 3 array"):
        cs.arm_move([0, 0], [1, 1], LIMITS[:, :2])
