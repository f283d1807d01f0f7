"""export(): the text `clearshape shape --export FORMAT` writes (export/export.hpp), byte for byte
with the same regenerate line, and its refusals with the CLI's message."""
import pytest

import clearshape

CASES = [  # (design options, export options): every format once
    (["--method", "zvd", "--frequency-hz", 3.32, "--zeta", 0.288], ["--export", "c-header", "--sample-time", 0.001]),
    (["--method", "ei", "--frequency-hz", 3.32, "--zeta", 0.288, "--vtol", 0.05], ["--export", "json", "--sample-time", 0.0005,
                                                                     "--discretization", "exact"]),
    (["--method", "zv", "--frequency-hz", 40, "--zeta", 0.1], ["--export", "klipper", "--export-axis", "x"]),
    (["--method", "zvd", "--frequency-hz", 40, "--zeta", 0.1], ["--export", "rrf"]),
]


def command_line(design_args, export_args):
    return " ".join(["clearshape shape", *map(str, design_args), *map(str, export_args)])


def options(design_args, export_args):
    a = dict(zip(design_args[::2], design_args[1::2]))
    e = dict(zip(export_args[::2], export_args[1::2]))
    return a, dict(sample_time_s=float(e.get("--sample-time", 0.0)), discretization=e.get("--discretization", "linear"),
                   klipper_axes=e.get("--export-axis", "xy")), e["--export"]


@pytest.mark.parametrize("design_args, export_args", CASES)
def test_export_is_the_clis_file(cli, design_args, export_args):
    ref = cli("shape", *design_args, *export_args)
    a, o, fmt = options(design_args, export_args)
    f, z = float(a["--frequency-hz"]), float(a["--zeta"])
    vtol = float(a["--vtol"]) if "--vtol" in a else None
    shaper = clearshape.design(a["--method"], frequency_hz=f, zeta=z)
    text, notes = clearshape.export(shaper, fmt, frequency_hz=f, zeta=z, vtol=vtol,
                                    command=command_line(design_args, export_args), **o)
    assert text == ref
    assert isinstance(notes, list)


def test_export_refusals_are_the_clis(cli):
    stderr = cli("shape", "--method", "zv", "--frequency-hz", 40, "--zeta", 0.1, "--export", "c-header",
                 "--sample-time", 0.001, "--export-name", "9bad", expect=2)
    s = clearshape.design("zv", frequency_hz=40, zeta=0.1)
    with pytest.raises(ValueError) as e:
        clearshape.export(s, "c-header", frequency_hz=40, zeta=0.1, sample_time_s=0.001, c_name="9bad")
    assert str(e.value) in stderr
    with pytest.raises(ValueError, match="allowed"):
        clearshape.export(s, "gcode")
    assert clearshape.export_formats() == ["json", "c-header", "klipper", "rrf"]
