"""arm_move(schedule="clearance-aware") against `clearshape arm move --shaper clearance-aware` on
the same move and options (the CLI is itself checked against the library's design in
tests/cli/test_arm_clearance_aware_cli.cpp): the same trajectory to the bit and the same design summary (the played move's residual against
unshaped is checked there); bad design options are refused."""
import numpy as np
import pytest
import clearshape as cs

from conftest import read_csv

# Move 9 of scara-2's pick-and-place moves (arm::pick_and_place_moves(arm, 12, 1)): its links
# rattle through their 0.5° plays (docs/arm.md §7)
FROM = [-0.86584301220675441, 1.261463100215928]
TO = [-0.10568976834805532, -0.95705166269656106]
LIMITS = np.array([[2.0, 20.0, 400.0], [2.0, 20.0, 400.0]])  # the CLI's defaults on both joints


def test_python_equals_the_cli(cli, tmp_path):
    out = cli("arm", "move", "--from=" + ",".join(map(repr, FROM)), "--to=" + ",".join(map(repr, TO)),
              "--shaper", "clearance-aware", "--evaluations", 12, "-o", tmp_path / "cli.csv")
    move = cs.arm_move(FROM, TO, LIMITS, schedule="clearance-aware", evaluations=12)
    written = read_csv(tmp_path / "cli.csv")
    np.testing.assert_array_equal(move["time_s"], written["time_s"])
    for j, name in enumerate(move["joint_names"]):
        np.testing.assert_array_equal(move["position_rad"][:, j], written[name + "_rad"])
    design = move["design"]
    assert design["evaluations"] == 12
    assert f"worst ratio to unshaped {design['worst_ratio']:.4f}" in out
    assert design["worse_than_unshaped"] == ("WORSE" in out)
    assert design["start_places"].shape == (5, 2)
    assert np.all(design["shaped_residual_m"] < design["unshaped_residual_m"])


@pytest.mark.parametrize("kwargs, named", [
    ({"evaluations": 5}, "evaluations"),
    ({"slots": 1}, "slots"),
    ({"grid_s": 2.0}, "grid_s"),
    ({"threads": 0}, "threads"),
    ({"start_places": [[0.0, 2.0]]}, "start_places"),
    ({"start_places": [[0.0, 0.0, 0.0]]}, "start_places"),
])
def test_bad_design_options_are_named(kwargs, named):
    with pytest.raises(ValueError, match=named):
        cs.arm_move(FROM, TO, LIMITS, schedule="clearance-aware", **kwargs)
