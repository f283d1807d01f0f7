"""arm_move(flank_margin=, flank_floor=) against `clearshape arm move --flank-margin --flank-floor`
on vertical-2's study move 17 (the CLI's peak shoulder acceleration is checked against the chain's
margin · |g_1| / M_11 in tests/cli/test_arm_flank_cli.cpp): the same trajectory to the bit for
every schedule, the lowered limits the CLI prints, and the range refused by name."""
import numpy as np
import pytest
import clearshape as cs

from conftest import read_csv

# Move 17 of vertical-2's pick-and-place moves (arm::pick_and_place_moves(arm, 20, 1)[17]): its
# shoulder ends gravity-loaded, |g_1| / M_11 = 9.43 rad/s² (docs/arm.md §7, "The flank-keeping stop")
FROM = [0.12453920851204048, -0.42277866939225239]
TO = [-1.2881144265618329, 0.40348152159789574]
LIMITS = np.array([[2.0, 20.0, 400.0], [2.0, 20.0, 400.0]])  # the CLI's defaults on both joints
SCHEDULES = [("unshaped", "none", []), ("fixed", "fixed", []), ("scheduled", "scheduled", []),
             ("clearance-aware", "clearance-aware", ["--evaluations", 10, "--design-settle-s", 0.3])]


@pytest.mark.parametrize("schedule, shaper, extra", SCHEDULES)
def test_python_equals_the_cli(cli, tmp_path, schedule, shaper, extra):
    out = cli("arm", "move", "--arm", "vertical-2", "--from=" + ",".join(map(repr, FROM)),
              "--to=" + ",".join(map(repr, TO)), "--shaper", shaper, *extra, "--flank-margin", 0.5,
              "--flank-floor", 0.1, "-o", tmp_path / "cli.csv")
    kwargs = {"evaluations": 10, "design_settle_s": 0.3} if extra else {}
    move = cs.arm_move(FROM, TO, LIMITS, arm="vertical-2", schedule=schedule, flank_margin=0.5, flank_floor=0.1,
                       **kwargs)
    written = read_csv(tmp_path / "cli.csv")
    np.testing.assert_array_equal(move["time_s"], written["time_s"])
    for j, name in enumerate(move["joint_names"]):
        np.testing.assert_array_equal(move["position_rad"][:, j], written[name + "_rad"])
    lowered = move["acceleration_limits_rad_s2"]
    assert lowered[0] < 0.5 * LIMITS[0, 1]
    assert "acceleration 20,20 -> " + ",".join(f"{a:.6g}" for a in lowered) + " rad/s²" in out
    plain = cs.arm_move(FROM, TO, LIMITS, arm="vertical-2")
    assert move["move_duration_s"] > plain["move_duration_s"]  # the price: a longer move
    np.testing.assert_array_equal(plain["acceleration_limits_rad_s2"], LIMITS[:, 1])


@pytest.mark.parametrize("kwargs, named", [
    ({"flank_margin": 1.5}, "flank_margin"),
    ({"flank_margin": -0.1}, "flank_margin"),
    ({"flank_margin": 0.5, "flank_floor": 0.0}, "flank_floor"),
    ({"flank_floor": 1.5}, "flank_floor"),
])
def test_out_of_range_is_named(kwargs, named):
    with pytest.raises(ValueError, match=named):
        cs.arm_move(FROM, TO, LIMITS, arm="vertical-2", **kwargs)
