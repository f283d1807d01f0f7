"""Designs are values (docs/design.md §3): Shaper equality, hashing and pickling (for
multiprocessing and Dask), and truth(name)'s error naming every name it knows."""
import pickle

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
