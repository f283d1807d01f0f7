"""Signals and command paths against `clearshape signal` on the same parameters."""
import numpy as np
import pytest

import clearshape
from conftest import deg_to_rad, rad_to_deg, read_csv


def test_types_match_the_cli_list():
    assert clearshape.signal_types()[:4] == ["step", "ramp", "sine", "prbs"]
    assert "amplitude" in clearshape.signal_parameters("step")


@pytest.mark.parametrize("args,kwargs", [
    (["--type", "step", "--amplitude", "20", "--rise-s", "0.1", "--rise-shape", "s-curve"],
     dict(type="step", amplitude=20, rise_s=0.1, rise_shape="s-curve")),
    (["--type", "sine", "--amplitude", "2", "--frequency-hz", "1.5", "--phase-deg", "30"],
     dict(type="sine", amplitude=2, frequency_hz=1.5, phase_rad=30 * np.pi / 180.0)),
    (["--type", "prbs", "--order", "7", "--bit-period-s", "0.02", "--amplitude", "1", "--seed", "5"],
     dict(type="prbs", order=7, bit_period_s=0.02, amplitude=1, seed=5)),
    (["--type", "stacked-steps", "--levels", "1,3,2", "--dwell-s", "0.4"],
     dict(type="stacked-steps", levels=[1, 3, 2], dwell_s=0.4)),
])
def test_signal_is_bit_identical_to_the_cli(cli, tmp_path, args, kwargs):
    out = tmp_path / "s.csv"
    cli("signal", *args, "--duration", "2", "--rate", "500", "-o", out)
    ref = read_csv(out)
    t, v = clearshape.signal(rate_hz=500, duration_s=2, **kwargs)
    np.testing.assert_array_equal(t, ref["time_s"])
    np.testing.assert_array_equal(v, ref["command"])


def test_position_path_matches_the_cli(cli, tmp_path):
    out = tmp_path / "p.csv"
    cli("signal", "--type", "step", "--amplitude", "20", "--path", "position", "--duration", "1", "-o", out)
    ref = read_csv(out)
    _, deg = clearshape.signal("step", amplitude=20, duration_s=1)
    r = clearshape.position_path(deg_to_rad(deg), 1e-3, initial_rad=0.0)  # as the CLI: the value before the start
    np.testing.assert_array_equal(rad_to_deg(r["commanded_rad"]), ref["commanded_deg"])
    np.testing.assert_array_equal(r["pulse_frequency_hz"], ref["pulse_frequency_hz"])


def test_speed_path_matches_the_cli(cli, tmp_path):
    out = tmp_path / "v.csv"
    cli("signal", "--type", "sine", "--amplitude", "12", "--frequency-hz", "2", "--path", "speed",
        "--duration", "1", "-o", out)
    ref = read_csv(out)
    _, u = clearshape.signal("sine", amplitude=12, frequency_hz=2, duration_s=1)
    r = clearshape.speed_path(u, 1e-3)
    np.testing.assert_array_equal(r["volts"], ref["daq_v"])
    assert r["clipped_samples"] > 0  # 12 V beyond the ±10 V D/A


def test_bad_parameter_raises_value_error_with_the_cli_message(cli):
    stderr = cli("signal", "--type", "prbs", "--order", "40", expect=2)
    with pytest.raises(ValueError) as e:
        clearshape.signal("prbs", order=40)
    assert "order" in str(e.value) and "40" in str(e.value)
    assert "[2, 31]" in str(e.value) and "[2, 31]" in stderr
    with pytest.raises(ValueError, match="not known"):
        clearshape.position_path(np.zeros(10), 1e-3, velocity_hold="sometimes")
    with pytest.raises(ValueError, match="one-dimensional"):
        clearshape.speed_path(np.zeros((2, 2)), 1e-3)
