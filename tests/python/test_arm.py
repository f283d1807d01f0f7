"""The arm bindings (docs/arm.md): simulate_arm on the built-in scara-2 and on one's own texts,
checked against closed forms (the tool's forward kinematics, the drive's steady state) and
against the refusals of the C++ reader."""
import numpy as np
import pytest

import clearshape as cs

DEG = np.pi / 180.0


def shoulder_move(gear, link_deg=5.0, samples=601):
    """A 0.3 s cosine move of the shoulder at the link, in motor degrees, 1 ms samples."""
    t = np.arange(samples) * 1e-3
    w = 0.5 - 0.5 * np.cos(np.pi * np.clip((t - 0.05) / 0.3, 0.0, 1.0))
    return np.vstack([w * link_deg * gear, np.zeros(samples)])


def test_builtin_arms_are_listed_with_their_texts():
    assert cs.arm_names() == ["scara-2", "vertical-2"]
    urdf, toml = cs.arm_text("vertical-2")
    assert '<robot name="vertical-2">' in urdf and 'name = "shoulder"' in toml
    with pytest.raises(ValueError, match="allowed: scara-2, vertical-2"):
        cs.arm_text("puma-560")


def test_scara_tool_and_motor_follow_their_closed_forms():
    run = cs.simulate_arm(shoulder_move(50.0), 1e-3, arm="scara-2", duration_s=0.6)
    q = run["link_angle_rad"]
    assert q.shape == (601, 2) and run["joints"] == ["shoulder", "elbow"]
    # planar two-link forward kinematics (L1 = 0.25 m, L2 = 0.20 m, shoulder at z = 0.2 m)
    x = 0.25 * np.cos(q[:, 0]) + 0.20 * np.cos(q[:, 0] + q[:, 1])
    y = 0.25 * np.sin(q[:, 0]) + 0.20 * np.sin(q[:, 0] + q[:, 1])
    np.testing.assert_allclose(run["tool_position_m"][:, 0], x, atol=1e-12)
    np.testing.assert_allclose(run["tool_position_m"][:, 1], y, atol=1e-12)
    np.testing.assert_allclose(run["tool_position_m"][:, 2], 0.2, atol=1e-12)
    # the Kp = 1 drive settles on the command: 250 motor degrees, 5° at the gearbox output
    assert run["motor_angle_rad"][-1, 0] == pytest.approx(250.0 * DEG, abs=1e-6)
    assert run["output_angle_rad"][-1, 0] == pytest.approx(5.0 * DEG, abs=1e-8)
    # the link ends within the play (±0.25°) of the output, and the play was hit
    assert abs(q[-1, 0] - run["output_angle_rad"][-1, 0]) < 0.26 * DEG
    assert any(e["onset"] and e["joint"] == 0 for e in run["events"])
    # the last link's IMU (planar closed form): ω_z = q̇1 + q̇2, +g along z, nothing out of the plane
    rate = run["link_rate_rad_s"]
    np.testing.assert_allclose(run["gyro_rad_s"][:, 2], rate[:, 0] + rate[:, 1], atol=1e-12)
    np.testing.assert_allclose(run["gyro_rad_s"][:, :2], 0.0, atol=1e-12)
    np.testing.assert_allclose(run["accel_m_s2"][:, 2], 9.80665, atol=1e-12)


def test_own_texts_without_play_make_the_link_follow():
    urdf, toml = cs.arm_text("scara-2")
    stiff = toml.replace("play_deg = 0.5", "play_deg = 0.0").replace(
        'law = "hunt-crossley"\nstiffness = 3000\nexponent = 1.0\nrestitution = 0.5',
        'law = "kelvin-voigt"\nstiffness = 200000\ndamping = 325\npolicy = "raw"')
    assert stiff.count("kelvin-voigt") == 1, "the shoulder's contact table was not found"
    run = cs.simulate_arm(shoulder_move(50.0), 1e-3, urdf=urdf, toml=stiff, duration_s=0.6)
    lag = run["link_angle_rad"][:, 0] - run["output_angle_rad"][:, 0]
    assert np.abs(lag).max() < 0.01 * DEG  # a stiff, damped flank: the link follows the output
    assert abs(lag[-1]) < 1e-6 * DEG


def test_bad_input_is_refused_naming_the_key():
    urdf, toml = cs.arm_text("scara-2")
    with pytest.raises(ValueError, match=r"joint\[0\]\.gear_ratio.*allowed: > 0"):
        cs.simulate_arm(shoulder_move(50.0), 1e-3, urdf=urdf, toml=toml.replace("gear_ratio = 50", "gear_ratio = -50"))
    with pytest.raises(ValueError, match="one row per joint"):
        cs.simulate_arm(np.zeros((3, 10)), 1e-3)
    with pytest.raises(ValueError, match="give both texts"):
        cs.simulate_arm(np.zeros((2, 10)), 1e-3, urdf=urdf)


def test_a_pulse_train_path_delivers_whole_counts():
    """[joint.drive.path] (docs/arm.md §4) comes with the TOML text: through the thesis's pulse
    train (3000 pulses per motor turn, 30 Hz) the shoulder's 250 motor degrees arrive as
    round(250 · 3000/360) = 2083 whole counts, 249.96°, where the ideal path delivers 250°."""
    urdf, toml = cs.arm_text("scara-2")
    pulses = toml.replace("[joint.contact]", '[joint.drive.path]\nkind = "pulse-train"\n[joint.contact]', 1)
    run = cs.simulate_arm(shoulder_move(50.0), 1e-3, urdf=urdf, toml=pulses, duration_s=0.6)
    assert run["motor_angle_rad"][-1, 0] == pytest.approx(2083 * 2 * np.pi / 3000, abs=1e-6)
    assert abs(run["motor_angle_rad"][-1, 0] - 250.0 * DEG) > 0.03 * DEG
    with pytest.raises(ValueError, match=r"joint\[0\]\.drive\.path\.kind.*allowed: ideal, pulse-train"):
        cs.simulate_arm(shoulder_move(50.0), 1e-3, urdf=urdf, toml=pulses.replace('"pulse-train"', '"analog"', 1))
