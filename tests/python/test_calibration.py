"""analyse_calibration: the analysis step of `clearshape rig calibrate` on recorded runs, without a
board. Runs of a known linear free decay x(t) = A·e^(−ζωt)·sin(ω_d t) after each step (seeded
gyro noise): the window starts where each step's command stops changing, the mode and damping
are the decay's, and the spectra, modes and candidates are those `clearshape recommend --json`
computes from the same runs written as CSV (the same C++ path, advise/recommend.hpp)."""
import json
import os
import subprocess

import numpy as np
import pytest

import clearshape

DT = 1e-3
F_HZ, ZETA = 12.0, 0.05
STEPS = [{"type": "step", "amplitude": a, "start_s": 0.5, "rise_s": 1.0 / 30.0} for a in (5.0, 10.0)]


def decay_runs():
    """Two 3 s runs: the step's command, and the gyro ringing down from where the command stops."""
    rng = np.random.default_rng(7)
    wn = 2 * np.pi * F_HZ
    wd = wn * np.sqrt(1 - ZETA ** 2)
    runs, starts = [], []
    for e in STEPS:
        t, command = clearshape.signal("step", rate_hz=1 / DT, duration_s=3.0,
                                       **{k: v for k, v in e.items() if k != "type"})
        t0 = (np.flatnonzero(np.diff(command))[-1] + 2) * DT  # one sample after the last change
        tau = t - t0
        gyro = np.where(tau >= 0, 20 * e["amplitude"] * np.exp(-ZETA * wn * tau) * np.sin(wd * tau), 0.0)
        gyro += rng.normal(0.0, 0.2, t.size)  # deg/s, the ITG-3205's order
        runs.append({"command": command, "gyro_deg_s": gyro, "time_s": t, "label": f"step {e['amplitude']:g}"})
        starts.append(t0)
    return runs, starts


def test_a_free_decay_gives_its_mode_where_each_step_ends():
    runs, starts = decay_runs()
    doc = clearshape.analyse_calibration(runs, DT, excitations=STEPS)
    np.testing.assert_allclose(doc["window_start_s"], starts, rtol=0, atol=1e-12)
    mode = doc["modes"][0]
    assert mode["frequency_hz"] == pytest.approx(F_HZ, rel=0.01)
    assert mode["damping_ratio"] == pytest.approx(ZETA, rel=0.2)
    assert doc["recommendation"] is not None and doc["command"] == "rig calibrate"


def test_it_equals_recommend_on_the_same_records(tmp_path):
    runs, starts = decay_runs()
    assert starts[0] == starts[1]  # one window for both files, as recommend --from-s takes
    paths = []
    for i, r in enumerate(runs):
        p = tmp_path / f"run{i}.csv"
        with open(p, "w", encoding="utf-8") as f:
            f.write("time_s,gyro_deg_s\n")
            f.writelines(f"{t!r},{g!r}\n" for t, g in zip(r["time_s"], r["gyro_deg_s"]))
        paths.append(str(p))
    data = [a for p in paths for a in ("--data", p)]
    cli = subprocess.run([os.environ["CLEARSHAPE_CLI"], "recommend", *data, "--column", "gyro_deg_s",
                          "--from-s", repr(starts[0]), "--json"], capture_output=True, text=True, check=True)
    expected = json.loads(cli.stdout)
    doc = clearshape.analyse_calibration(runs, DT, excitations=STEPS)
    for key in ("modes", "candidates", "recommendation"):
        assert doc[key] == expected[key], key


def test_bad_runs_are_refused_naming_the_field():
    runs, _ = decay_runs()
    del runs[1]["gyro_deg_s"]
    with pytest.raises(ValueError, match=r"runs\[1\]\.gyro_deg_s is missing"):
        clearshape.analyse_calibration(runs, DT, excitations=STEPS)
    runs, _ = decay_runs()
    runs[0]["gyro_deg_s"] = runs[0]["gyro_deg_s"][:-1]
    with pytest.raises(ValueError, match=r"runs\[0\]: every column must have command's 3001 samples"):
        clearshape.analyse_calibration(runs, DT, excitations=STEPS)
    with pytest.raises(ValueError, match="2 runs for 1 excitations"):
        clearshape.analyse_calibration(decay_runs()[0], DT, excitations=STEPS[:1])
