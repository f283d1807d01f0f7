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
    # the built-in truths of rig/builtin_truths.hpp and the calibration's prior, by name
    assert {"thesis", "large-play", "worn-coupling", "uncalibrated"} <= set(clearshape.truth_names())
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
    # step() refuses a complex sample too (NumPy's complex scalars would truncate through float()),
    # naming the argument, and steps nothing; real NumPy scalars are taken as floats.
    for bad in (1 + 1j, np.complex128(1.0), np.complex64(2.0)):
        with pytest.raises(ValueError, match=r"value = .* is complex"):
            held.step(bad)
    with pytest.raises(TypeError, match="value must be a real number, got str"):
        held.step("1.0")
    assert held.step(np.float32(1.0)) == twin.step(1.0) and held.step(np.int64(1)) == twin.step(1.0)
    assert list(clearshape.shape(s, [0.0, 1.0, 1.0], 1e-3, extend=False)) == list(clearshape.shape(s, np.array([0.0, 1.0, 1.0]), 1e-3, extend=False))


def _worn_truth():
    """A truth with fields off their defaults everywhere the bindings reach."""
    t = clearshape.truth("worn-coupling")
    t.clearance_rad = np.deg2rad(0.7)
    t.set_contact("speed", stiffness=12.5, damping=0.25)
    t.variation = {"position_gain_rel_sigma": 1e-3, "flank_damping_rel_sigma": 0.2}
    return t


def _run(truth, mode):
    t, u = clearshape.signal("step", amplitude=10, start_s=0.05, duration_s=0.6)
    command = np.deg2rad(u) if mode == "position" else u / 10.0
    return clearshape.simulate(command, 1e-3, mode, truth, duration_s=0.6)


def _remote_run(truth, mode):
    """In a spawned worker: the truth as received and its run."""
    return truth, _run(truth, mode)


def test_truths_compare_and_pickle_by_value_and_simulate_alike():
    for name in clearshape.truth_names():
        t = clearshape.truth(name)
        back = pickle.loads(pickle.dumps(t))
        assert back is not t and back == t and back == clearshape.truth(name)
    assert clearshape.truth("thesis") != clearshape.truth("large-play")
    worn = _worn_truth()
    assert worn != clearshape.truth("worn-coupling") and (worn == "worn") is False
    with pytest.raises(TypeError):
        hash(worn)  # mutable: no hash
    back = pickle.loads(pickle.dumps(worn, protocol=pickle.HIGHEST_PROTOCOL))
    assert back == worn and back.contact("speed") == worn.contact("speed") and back.variation == worn.variation
    copied = worn.copy()
    copied.set_contact("position", exponent=1.2)
    assert copied != worn  # a change anywhere breaks equality
    for mode in ("position", "speed"):  # every column bit for bit: the pickle carries the whole rig
        a, b = _run(worn, mode), _run(back, mode)
        for key, value in a.items():
            assert np.array_equal(value, b[key]), (mode, key)


def test_truth_crosses_to_a_spawned_process():
    import concurrent.futures
    import multiprocessing

    worn = _worn_truth()
    context = multiprocessing.get_context("spawn")  # a fresh interpreter: nothing shared but the pickle
    with concurrent.futures.ProcessPoolExecutor(max_workers=1, mp_context=context) as pool:
        received, run = pool.submit(_remote_run, worn, "speed").result(timeout=120)
    assert received == worn
    here = _run(worn, "speed")
    for key in ("link_angle_rad", "motor_angle_rad", "gyro_raw", "contact_torque_n_m"):
        assert np.array_equal(run[key], here[key]), key


def test_a_malformed_truth_state_is_refused_naming_the_field():
    state = clearshape.thesis_truth().__getstate__()
    del state["link"]["mass_kg"]
    with pytest.raises(ValueError, match=r"link\.mass_kg is missing"):
        clearshape.RigTruth.__new__(clearshape.RigTruth).__setstate__(state)
    state = clearshape.thesis_truth().__getstate__()
    state["position_drive"]["delay_s"] = -1.0
    with pytest.raises(ValueError, match=r"drive\.delay_s"):
        clearshape.RigTruth.__new__(clearshape.RigTruth).__setstate__(state)
