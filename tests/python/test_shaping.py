"""Shaper design, residual vibration, sensitivity and shaping against `clearshape shape` and
`clearshape sensitivity` on the same mode (same C++ code: bit-identical)."""
import numpy as np
import pytest

import clearshape
from conftest import read_csv, write_csv

F_HZ, ZETA = 3.32, 0.288  # the thesis's speed-mode drive mode (Eq. 4.2)


def cli_impulses(doc):
    return np.array([i["time_s"] for i in doc["impulses"]]), np.array([i["amplitude"] for i in doc["impulses"]])


@pytest.mark.parametrize("method,extra_cli,extra_py", [
    ("zv", [], {}), ("zvd", [], {}), ("zvdd", [], {}), ("zvddd", [], {}), ("mzv", [], {}),
    ("ei", [], {}), ("ei2", [], {}), ("ei3", ["--vtol", "0.03"], {"vtol": 0.03}), ("um-zv", [], {}),
    ("si", ["--band-low-hz", "2.5", "--band-high-hz", "4.2"], {"band_low_hz": 2.5, "band_high_hz": 4.2}),
    ("zvd", ["--second-frequency-hz", "9", "--second-zeta", "0.05"],
     {"second_frequency_hz": 9, "second_zeta": 0.05}),
])
def test_design_is_bit_identical_to_the_cli(cli_json, method, extra_cli, extra_py):
    zeta = 0.1 if method == "ei3" else ZETA  # EI3 exists up to ζ ≈ 0.27
    doc = cli_json("shape", "--method", method, "--frequency-hz", F_HZ, "--zeta", zeta, *extra_cli)
    s = clearshape.design(method, frequency_hz=F_HZ, zeta=zeta, **extra_py)
    t, a = cli_impulses(doc)
    np.testing.assert_array_equal(s.times_s, t)
    np.testing.assert_array_equal(s.amplitudes, a)
    assert s.duration_s == doc["duration_s"]
    assert s.method == doc["method"]


def test_custom_and_wn():
    s = clearshape.design("custom", impulses=[(0, 1), (0.05, 1)])
    np.testing.assert_array_equal(s.amplitudes, [0.5, 0.5])
    a = clearshape.design("zv", wn_rad_s=2 * np.pi * F_HZ, zeta=ZETA)
    b = clearshape.design("zv", frequency_hz=F_HZ, zeta=ZETA)
    np.testing.assert_array_equal(a.times_s, b.times_s)


def test_residual_vibration_against_eq_2_19_in_numpy():
    # Independent reference: Eq. 2.19 written out (Singer & Seering), V = e^{-ζωt_N}·|Σ A e^{ζωt}e^{iωd t}|.
    s = clearshape.design("zvd", frequency_hz=F_HZ, zeta=ZETA)
    for r in (0.7, 1.0, 1.3):
        w = 2 * np.pi * F_HZ * r
        wd = w * np.sqrt(1 - ZETA**2)
        t, a = s.times_s, s.amplitudes
        c = np.sum(a * np.exp(ZETA * w * t) * np.cos(wd * t))
        d = np.sum(a * np.exp(ZETA * w * t) * np.sin(wd * t))
        v = np.exp(-ZETA * w * t[-1]) * np.hypot(c, d)
        assert clearshape.residual_vibration(s, F_HZ * r, ZETA) == pytest.approx(v, abs=1e-12)


def test_sensitivity_is_bit_identical_to_the_cli(cli, tmp_path):
    out = tmp_path / "v.csv"
    cli("sensitivity", "--method", "ei", "--frequency-hz", F_HZ, "--zeta", ZETA, "--from", 0.5, "--to", 1.5,
        "--points", 101, "-o", out)
    ref = read_csv(out)
    s = clearshape.design("ei", frequency_hz=F_HZ, zeta=ZETA)
    r, v = clearshape.sensitivity(s, F_HZ, ZETA, 0.5, 1.5, 101)
    np.testing.assert_array_equal(r, ref["frequency_ratio"])
    np.testing.assert_array_equal(v, ref["residual"])
    lo, hi = clearshape.insensitivity(s, F_HZ, ZETA, 0.05)
    assert lo < 1 < hi and (hi - lo) > 0.3  # EI: wide band at Vtol = 5 %


@pytest.mark.parametrize("discretization", ["linear", "exact"])
def test_offline_shaping_is_bit_identical_to_the_cli(cli, tmp_path, discretization):
    t, u = clearshape.signal("trapezoid", amplitude=10, start_s=0.1, rise_s=0.2, hold_s=0.3, fall_s=0.2,
                             duration_s=1.5)
    write_csv(tmp_path / "in.csv", {"time_s": t, "u": u})
    cli("shape", "--method", "zvdd", "--frequency-hz", F_HZ, "--zeta", ZETA, "--input", tmp_path / "in.csv",
        "--column", "u", "--output", tmp_path / "out.csv", "--discretization", discretization)
    ref = read_csv(tmp_path / "out.csv")
    s = clearshape.design("zvdd", frequency_hz=F_HZ, zeta=ZETA)
    mode = dict(frequency_hz=F_HZ, zeta=ZETA) if discretization == "exact" else {}
    y = clearshape.shape(s, u, 1e-3, discretization=discretization, **mode)
    np.testing.assert_array_equal(y, ref["u_shaped"])


def test_streaming_equals_offline_to_rounding():
    _, u = clearshape.signal("step", amplitude=5, start_s=0.05, duration_s=1)
    s = clearshape.design("zvd", frequency_hz=F_HZ, zeta=ZETA)
    offline = clearshape.shape(s, u, 1e-3, extend=False)
    stream = clearshape.StreamingShaper(s, 1e-3)
    np.testing.assert_allclose(stream.process(u), offline, rtol=0, atol=1e-12)
    stream.reset(0.0)
    assert stream.step(5.0) == pytest.approx(5.0 * s.amplitudes[0], abs=1e-15)


def test_design_errors_are_value_errors_with_the_cli_message(cli):
    stderr = cli("shape", "--method", "zvd", "--frequency-hz", F_HZ, "--zeta", 1.2, expect=2)
    with pytest.raises(ValueError) as e:
        clearshape.design("zvd", frequency_hz=F_HZ, zeta=1.2)
    assert str(e.value) in stderr
    with pytest.raises(ValueError, match="exactly one"):
        clearshape.design("zv", zeta=0.1)
    with pytest.raises(ValueError, match="allowed"):
        clearshape.design("zz", frequency_hz=1, zeta=0.1)
