"""Designs are values (docs/design.md §3): Shaper equality, hashing and pickling (for
multiprocessing and Dask), and truth(name)'s error naming every name it knows."""
import pickle

import numpy as np

import pytest

import clearshape


def test_shapers_compare_by_value_and_pickle_to_the_same_impulses():
    a = clearshape.design("zvd", frequency_hz=3.32, zeta=0.288)
    b = clearshape.design("zvd", frequency_hz=3.32, zeta=0.288)
    assert a is not b and a == b and hash(a) == hash(b)
    assert a != clearshape.design("zvd", frequency_hz=3.33, zeta=0.288)
    assert a != clearshape.design("zv", frequency_hz=3.32, zeta=0.288)
    assert (a == "zvd") is False
    c = pickle.loads(pickle.dumps(a))
    assert c == a and c.method == "zvd"
    assert list(c.times_s) == list(a.times_s) and list(c.amplitudes) == list(a.amplitudes)  # bit for bit
    # An unnormalised custom shaper keeps its amplitudes through a pickle.
    raw = clearshape.Shaper("custom", [(0.0, 2.0), (0.1, 1.0)], normalize=False)
    assert list(pickle.loads(pickle.dumps(raw)).amplitudes) == [2.0, 1.0]


def test_truth_error_lists_every_name():
    with pytest.raises(ValueError) as e:
        clearshape.truth("nope")
    for name in clearshape.truth_names():
        assert name in str(e.value)
    assert "uncalibrated" in clearshape.truth_names()
    assert clearshape.truth("uncalibrated").clearance_rad == clearshape.uncalibrated_truth().clearance_rad


def test_shape_and_streaming_refuse_nan_and_complex_alike_and_step_holds():
    s = clearshape.design("zv", frequency_hz=5.0, zeta=0.1)
    u = np.ones(50)
    u[10] = np.nan
    for call in (lambda: clearshape.shape(s, u, 1e-3), lambda: clearshape.StreamingShaper(s, 1e-3).process(u)):
        with pytest.raises(ValueError, match=r"values\[10\] = nan is not finite"):
            call()
    c = np.ones(50) * (1 + 1j)
    for call in (lambda: clearshape.shape(s, c, 1e-3), lambda: clearshape.StreamingShaper(s, 1e-3).process(c)):
        with pytest.raises(ValueError, match="complex"):
            call()
    # A refused array steps nothing; step() holds a NaN as the real-time path (shaping/streaming.hpp).
    stream = clearshape.StreamingShaper(s, 1e-3)
    with pytest.raises(ValueError):
        stream.process(u)
    ok = np.r_[0.0, np.ones(49)]  # from rest, as the stream's history
    np.testing.assert_allclose(stream.process(ok), clearshape.shape(s, ok, 1e-3, extend=False), rtol=0, atol=1e-12)
    held, twin = clearshape.StreamingShaper(s, 1e-3), clearshape.StreamingShaper(s, 1e-3)
    ramp = np.linspace(0.0, 1.0, 80)
    held.process(ramp), twin.process(ramp)
    assert held.step(float("nan")) == twin.step(1.0)  # the previous input (1.0) in its place
    assert list(clearshape.shape(s, [0.0, 1.0, 1.0], 1e-3, extend=False)) == list(clearshape.shape(s, np.array([0.0, 1.0, 1.0]), 1e-3, extend=False))
