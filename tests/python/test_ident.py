"""identify and modes against `clearshape identify` / `clearshape modes` on the same record
(same C++ code and the same samples: bit-identical), and against the known true parameters."""
import numpy as np
import pytest

import clearshape
from conftest import write_csv

TS = 1e-3


def decay(f_hz=4.0, zeta=0.05, n=3000, seed=2):
    t = np.arange(n) * TS
    wn = 2 * np.pi * f_hz
    wd = wn * np.sqrt(1 - zeta**2)
    y = np.exp(-zeta * wn * t) * np.cos(wd * t) + 0.2
    return y + 1e-3 * np.random.default_rng(seed).standard_normal(n)


def test_modes_free_response_matches_the_cli_and_the_truth(cli_json, tmp_path):
    y = decay()
    write_csv(tmp_path / "d.csv", {"y": y})
    doc = cli_json("modes", "--data", tmp_path / "d.csv", "--output-column", "y", "--sample-time", TS)
    r = clearshape.modes(y, TS)
    m = r["modes"][0]
    assert m["natural_frequency_hz"] == pytest.approx(4.0 * 1.0, rel=2e-3)
    assert m["damping_ratio"] == pytest.approx(0.05, rel=3e-2)
    ref = doc["modes"][0]
    assert m["natural_frequency_hz"] == ref["frequency_hz"]
    assert m["damping_ratio"] == ref["damping_ratio"]


def test_identify_first_order_matches_the_cli_and_the_truth(cli_json, tmp_path):
    # A first-order lag Kp = 2, Tp1 = 0.05 s, exact ZOH discretisation, driven by a PRBS.
    _, u = clearshape.signal("prbs", order=7, bit_period_s=0.02, amplitude=1, duration_s=2.0)
    a = np.exp(-TS / 0.05)
    y = np.zeros_like(u)
    for k in range(1, len(u)):
        y[k] = a * y[k - 1] + 2.0 * (1 - a) * u[k - 1]
    y += 1e-4 * np.random.default_rng(1).standard_normal(len(u))
    write_csv(tmp_path / "io.csv", {"u": u, "y": y})
    doc = cli_json("identify", "--model", "P1", "--data", tmp_path / "io.csv", "--input-column", "u",
                   "--output-column", "y", "--sample-time", TS)
    r = clearshape.identify(u, y, TS, model="P1")
    assert r["parameters"]["Kp"] == pytest.approx(2.0, rel=1e-3)
    assert r["parameters"]["Tp1"] == pytest.approx(0.05, rel=1e-2)
    for name in ("Kp", "Tp1"):  # the same C++ fit on the same samples: the same doubles
        assert r["parameters"][name] == doc["parameters"][name]["value"]
        assert r["std_dev"][name] == doc["parameters"][name]["std"]
    assert r["fit_percent"] == doc["fit_percent"] and r["loss"] == doc["loss"]
    with pytest.raises(ValueError, match="P"):
        clearshape.identify(u, y, TS, model="Q9")
