"""Sweeps: the points, local and resumed runs, the Dask LocalCluster (two worker processes on
127.0.0.1) and the CLI all give byte-identical results; failures are kept per point; the
metrics are those of a direct evaluation with the bindings."""
import json
import os
import shutil
import signal
import subprocess
import sys
import time

import h5py
import numpy as np
import pytest

import clearshape
from clearshape.sweep import run_sweep
from clearshape.sweep_spec import Sweep, SweepError

SWEEP = """
[sweep]
seed = 7
samples = 2
duration_s = 1.2
batch = 3
plot = ["frequency_error", "contact_damping"]

[fixed]
mode = "position"
signal = "step"
amplitude = 20
design_frequency_hz = 6.5
zeta = 0.05

[grid]
clearance_deg = [0.032, 0.5]
shaper = ["zv", "ei3"]
frequency_error = [0.0, 0.2]

[random]
contact_damping = [0.05, 0.3]
"""  # 2 × 2 × 2 grid × 2 draws = 16 points; ei3 at ζ = 0.05 exists, so every point runs


def files(out):
    names = ("results.h5", "results.csv", "results.json", "improvement_map.png")
    return {n: open(os.path.join(out, n), "rb").read() for n in names}


@pytest.fixture(scope="module")
def sweep_file(tmp_path_factory):
    p = tmp_path_factory.mktemp("sweep") / "sweep.toml"
    p.write_text(SWEEP)
    return p


@pytest.fixture(scope="module")
def local(sweep_file, tmp_path_factory):
    out = str(tmp_path_factory.mktemp("local"))
    summary = run_sweep(sweep_file, out, workers=2, quiet=True)
    return out, summary


def test_points_grid_times_draws(sweep_file):
    pts = Sweep.load(sweep_file).points()
    assert len(pts) == 16
    assert [p["index"] for p in pts] == list(range(16))
    assert {(p["clearance_deg"], p["shaper"], p["frequency_error"]) for p in pts} == {
        (c, s, e) for c in (0.032, 0.5) for s in ("zv", "ei3") for e in (0.0, 0.2)}
    assert all(0.05 <= p["contact_damping"] <= 0.3 for p in pts)
    assert pts == Sweep.load(sweep_file).points()  # seeded


def test_local_results_and_metrics(local, sweep_file):
    out, summary = local
    assert summary["points"] == 16 and summary["failed"] == 0
    with h5py.File(os.path.join(out, "results.h5")) as f:
        g = f["points"]
        assert list(f.attrs["columns"].astype(str))[:2] == ["index", "seed"]
        md_u, md_s, imp = g["md_unshaped"][()], g["md_shaped"][()], g["improvement_percent"][()]
        np.testing.assert_allclose(imp, (md_u - md_s) / md_u * 100, rtol=1e-12)
        shaper = g["shaper"][()].astype(str)
        err = g["frequency_error"][()]
        # Physics: a shaper designed on the mode removes more than one designed 20 % off (ZV).
        zv = shaper == "zv"
        assert imp[zv & (err == 0)].mean() > imp[zv & (err == 0.2)].mean()
    # One point again, directly with the bindings: the same numbers.
    p = Sweep.load(sweep_file).points()[5]
    t = clearshape.thesis_truth()
    t.clearance_rad = p["clearance_deg"] * np.pi / 180.0
    t.set_contact("position", damping=p["contact_damping"])
    t.variation = {k: 0.0 for k in t.variation}
    _, u = clearshape.signal("step", amplitude=20, start_s=0.1, duration_s=1.2)
    r = clearshape.simulate(u * np.pi / 180.0, 1e-3, "position", t, duration_s=1.2, seed=p["seed"], sensor_noise=False)
    md = clearshape.mean_deviation(r["link_angle_rad"] * 180.0 / np.pi, 1e-3, search_from_s=0.1)["mean_deviation"]
    doc = json.load(open(os.path.join(out, "results.json")))
    assert doc["points"][5]["md_unshaped"] == md


def test_docs_name_the_columns_the_files_hold(local):
    """docs/sweeps.md's metric table names exactly the metric columns of results.h5 (issue 22
    item 13: it named md_unshaped_deg_s where the files hold md_unshaped)."""
    import re
    from pathlib import Path
    from clearshape.sweep_run import METRICS
    text = (Path(__file__).resolve().parents[2] / "docs" / "sweeps.md").read_text()
    table = text[text.index("| column | meaning |"):]
    table = table[:table.index("\n\n")]
    documented = set(re.findall(r"`([a-z_]+)`", "\n".join(row.split("|")[1] for row in table.splitlines()[2:])))
    out, _ = local
    with h5py.File(os.path.join(out, "results.h5")) as f:
        columns = set(f.attrs["columns"].astype(str))
    assert documented == set(METRICS) | {"status"}
    assert documented <= columns


def test_improvement_map(local):
    from clearshape.sweep_plot import improvement_map

    out, _ = local
    doc = json.load(open(os.path.join(out, "results.json")))
    xl, yl, mean, count = improvement_map(doc["points"], "frequency_error", "contact_damping", bins=2)
    assert xl == [0.0, 0.2] and len(yl) == 2 and count.sum() == 16
    pts = doc["points"]
    lo = [p["improvement_percent"] for p in pts if p["frequency_error"] == 0.0]
    assert np.nansum(mean[:, 0] * count[:, 0]) / count[:, 0].sum() == pytest.approx(np.mean(lo), rel=1e-12)
    png = open(os.path.join(out, "improvement_map.png"), "rb").read()
    assert png[:8] == b"\x89PNG\r\n\x1a\n"


def test_results_and_batches_follow_the_umask(local):
    """Files like any other (issue 23: they were 0600): 0666 less the umask, 0644 under 022."""
    out, _ = local
    mask = os.umask(0o022)
    os.umask(mask)
    state = os.path.join(out, ".sweep")
    paths = [os.path.join(out, n) for n in files(out)]
    paths += [os.path.join(state, n) for n in os.listdir(state)] if os.path.isdir(state) else []
    for path in paths:
        assert oct(os.stat(path).st_mode & 0o777) == oct(0o666 & ~mask), path


def test_resume_gives_the_same_bytes(local, sweep_file, tmp_path):
    out, _ = local
    resumed = str(tmp_path / "resumed")
    shutil.copytree(out, resumed)
    state = os.path.join(resumed, ".sweep")
    batches = sorted(os.listdir(state))
    for name in batches[::2]:  # as if killed half-way
        os.unlink(os.path.join(state, name))
    for name in ("results.h5", "results.csv", "results.json", "improvement_map.png"):
        os.unlink(os.path.join(resumed, name))
    s = run_sweep(sweep_file, resumed, workers=1, quiet=True)
    assert s["ran"] == sum(3 if i < 5 else 1 for i in range(0, 6, 2))
    assert files(resumed) == files(out)


def test_dask_local_cluster_is_byte_identical(local, sweep_file, tmp_path):
    from distributed import Client, LocalCluster

    out, _ = local
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address=None) as cluster, Client(cluster) as client:
        s = run_sweep(sweep_file, str(tmp_path / "dask"), scheduler=client, quiet=True)
    assert s["failed"] == 0
    assert files(str(tmp_path / "dask")) == files(out)


def test_dask_retries_failed_tasks_and_never_loses_points(local, sweep_file, tmp_path):
    """A task that fails is retried; one that keeps failing is reported and left for the rerun."""
    from distributed import Client, LocalCluster

    from clearshape.sweep_run import run_batch

    out, _ = local
    marks = str(tmp_path / "marks")
    os.makedirs(marks)

    def flaky(points, settings, fail_times=1):  # fails the first `fail_times` tries of each batch
        mark = os.path.join(marks, f"batch-{points[0]['index']}")
        tries = sum(n.startswith(os.path.basename(mark) + ".") for n in os.listdir(marks))
        if tries < fail_times:
            open(f"{mark}.{tries}", "w").close()
            raise OSError(f"worker lost (simulated), try {tries}")
        return run_batch(points, settings)

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address=None) as cluster, Client(cluster) as client:
        s = run_sweep(sweep_file, str(tmp_path / "retried"), scheduler=client, retries=1, quiet=True,
                      batch_function=flaky)
        assert s["failed"] == 0
        assert files(str(tmp_path / "retried")) == files(out)
        assert len(os.listdir(marks)) == 6  # every one of the 6 tasks failed once and was retried
        for name in os.listdir(marks):
            os.unlink(os.path.join(marks, name))
        always = lambda points, settings: flaky(points, settings, fail_times=10 if points[0]["index"] == 3 else 0)  # noqa: E731
        with pytest.raises(RuntimeError, match="1 task\\(s\\) failed after their retries.*rerun"):
            run_sweep(sweep_file, str(tmp_path / "lost"), scheduler=client, retries=2, quiet=True,
                      batch_function=always)
    assert len(os.listdir(tmp_path / "lost" / ".sweep")) == 5  # the other five batches are kept
    s = run_sweep(sweep_file, str(tmp_path / "lost"), workers=1, quiet=True)  # the rerun does the rest
    assert s["ran"] == 3
    assert files(str(tmp_path / "lost")) == files(out)


def test_cli_sweep_matches_and_validates(local, sweep_file, tmp_path):
    out, _ = local
    cli = os.environ["CLEARSHAPE_CLI"]
    r = subprocess.run([cli, "sweep", str(sweep_file), "--out", str(tmp_path / "cli"), "--workers", "2"],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert "16/16 points" in r.stderr
    assert files(str(tmp_path / "cli")) == files(out)
    bad = tmp_path / "bad.toml"
    bad.write_text(SWEEP.replace("zeta = 0.05", "zeta = 1.5"))
    r = subprocess.run([cli, "sweep", str(bad), "--out", str(tmp_path / "bad")], capture_output=True, text=True)
    assert r.returncode == 2
    assert f"{bad}: fixed.zeta = 1.5 is out of range; allowed: [0, 0.999]" in r.stderr


def test_failed_points_are_kept_with_their_reason(tmp_path):
    text = SWEEP.replace("zeta = 0.05", "zeta = 0.4").replace("samples = 2", "samples = 1").replace(
        'plot = ["frequency_error", "contact_damping"]', 'plot = ["clearance_deg", "frequency_error"]')
    s = run_sweep(Sweep(text, "inline.toml"), str(tmp_path), workers=1, quiet=True)
    assert s["points"] == 8 and s["failed"] == 4  # EI3 does not exist at ζ = 0.4
    assert all("ValueError" in why and "ei3" in why.lower() for _, why in s["failures"])
    doc = json.load(open(tmp_path / "results.json"))
    assert sum(p["status"] == "ok" for p in doc["points"]) == 4


def test_the_example_sweep_file_parses():
    here = os.path.dirname(os.path.abspath(__file__))
    sweep = Sweep.load(os.path.join(here, "..", "..", "studies", "sweep-play.toml"))
    assert len(sweep.points()) == 5 * 5 * 3 * 4
    assert sweep.axes() == ["clearance_deg", "frequency_error", "shaper", "contact_damping"]


def test_the_sweep_file_is_never_an_output(tmp_path):
    f = tmp_path / "results.csv"
    f.write_text(SWEEP)
    with pytest.raises(ValueError, match="also the output"):
        run_sweep(f, str(tmp_path), workers=1, quiet=True)
    assert f.read_text() == SWEEP


def test_bad_sweep_files():
    with pytest.raises(SweepError, match="x.toml: grid.shaper\\[0\\] = 'zq' is not known"):
        Sweep(SWEEP.replace('["zv", "ei3"]', '["zq"]'), "x.toml")
    with pytest.raises(SweepError, match="design_frequency_hz"):
        Sweep(SWEEP.replace("design_frequency_hz = 6.5", ""), "x.toml")
    with pytest.raises(SweepError, match="does not vary"):
        Sweep(SWEEP.replace('"contact_damping"]', '"zeta"]'), "x.toml")
    with pytest.raises(SweepError, match="also in"):
        Sweep(SWEEP.replace("zeta = 0.05", "zeta = 0.05\nclearance_deg = 1"), "x.toml")


# Issue 21 item 7: a 1000 × 1000 × 1000 grid printed nothing and grew ~150 MB/s until killed.
# Its size is known from the file: it is refused at once with the estimate and the option that
# allows it, before the output folder exists.
def test_a_runaway_grid_is_refused_with_its_estimate_before_any_output(tmp_path):
    big = ", ".join(f"{0.001 * (i + 1):.3f}" for i in range(1000))
    text = SWEEP.replace("clearance_deg = [0.032, 0.5]", f"clearance_deg = [{big}]").replace(
        "frequency_error = [0.0, 0.2]", f"frequency_error = [{big}]").replace("samples = 2", "samples = 500")
    sweep = Sweep(text, "big.toml")
    assert sweep.count() == 1000 * 2 * 1000 * 500
    out = tmp_path / "out"
    t0 = time.monotonic()
    with pytest.raises(SweepError) as e:
        run_sweep(sweep, str(out), workers=1, quiet=True)
    assert time.monotonic() - t0 < 5
    message = str(e.value)
    assert "1,000,000,000 points (grid 1000 × 2 × 1000 × 500 draws)" in message
    assert "the limit is 1,000,000 points" in message and "--max-points 1000000000" in message
    assert not out.exists()
    # Through the CLI: exit 2, the same numbers, nothing created.
    bad = tmp_path / "big.toml"
    bad.write_text(text)
    r = subprocess.run([os.environ["CLEARSHAPE_CLI"], "sweep", str(bad), "--out", str(out)],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 2, r.stderr
    assert "--max-points 1000000000" in r.stderr
    assert not out.exists()
    # Within a raised limit the estimate is printed before the work starts.
    small = Sweep(SWEEP, "small.toml")
    assert small.estimate() == {"points": 16, "runs": 32, "samples": 32 * 1201, "memory_bytes": 16 * 2048}
    with pytest.raises(SweepError, match="limit is 15 points"):
        run_sweep(small, str(out), workers=1, quiet=True, max_points=15)


# The exit-code list: `sweep --out FILE` exited 1 with a raw errno text.
def test_an_output_that_is_a_file_is_named(sweep_file, tmp_path):
    f = tmp_path / "results"
    f.write_text("mine")
    r = subprocess.run([os.environ["CLEARSHAPE_CLI"], "sweep", str(sweep_file), "--out", str(f)],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 2, r.stderr
    assert f"--out {f} is a file, not a folder" in r.stderr
    assert f.read_text() == "mine"


def _children(pid):
    try:
        with open(f"/proc/{pid}/task/{pid}/children") as f:
            return [int(c) for c in f.read().split()]
    except FileNotFoundError:
        return []


def _alive(pid):
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().split(")")[-1].split()[0] != "Z"
    except FileNotFoundError:
        return False


# Issue 21 item 8: after SIGTERM or kill -9 of the sweep, its pool workers kept computing under
# PID 1. They now die with their parent (PR_SET_PDEATHSIG) and SIGTERM shuts the pool down.
@pytest.mark.parametrize("signo", [signal.SIGTERM, signal.SIGKILL])
def test_pool_workers_die_with_their_parent(tmp_path, signo):
    # Long enough that an idle machine is still in the first batches when the signal comes: 200
    # draws × 8 grid points of 60 s runs (a few minutes of work; the test stops it after ~1 s).
    slow = (SWEEP.replace("duration_s = 1.2", "duration_s = 60.0").replace("batch = 3", "batch = 4")
            .replace("samples = 2", "samples = 200"))
    assert slow.count("60.0") == 1 and "samples = 200" in slow
    f = tmp_path / "slow.toml"
    f.write_text(slow)
    env = dict(os.environ)
    p = subprocess.Popen([sys.executable, "-m", "clearshape.sweep", str(f), "--out", str(tmp_path / "out"),
                          "--workers", "2", "--quiet"], env=env, stderr=subprocess.PIPE, text=True)
    workers = []
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline and len(workers) < 2:
        workers = _children(p.pid)
        time.sleep(0.1)
    assert len(workers) >= 2, "the pool did not start"
    time.sleep(1.0)  # the workers are inside their first batch (60 s runs)
    os.kill(p.pid, signo)
    p.wait(timeout=30)
    err = p.stderr.read()
    assert p.returncode == -signo, err
    deadline = time.monotonic() + 5
    while time.monotonic() < deadline and any(_alive(w) for w in workers):
        time.sleep(0.1)
    left = [w for w in workers if _alive(w)]
    for w in left:
        os.kill(w, signal.SIGKILL)
    assert not left, f"pool workers {left} outlived the sweep"


# Issue 23: `--scheduler tcp://HOST:PORT` always failed ("No clients found", exit 2): the tests
# above pass a Client, never an address. Here a real `dask-scheduler` and two `dask-worker`
# processes (Debian's python3-distributed, the same interpreter) are started by the test and
# only the address string is handed to run_sweep and to the CLI.
def _dask_cli(name, *args, log):
    return subprocess.Popen([sys.executable, "-m", f"distributed.cli.dask_{name}", *args],
                            stdout=log, stderr=log, env=dict(os.environ))


def _stop(processes):
    for p in processes:
        p.terminate()
    for p in processes:
        try:
            p.wait(timeout=20)
        except subprocess.TimeoutExpired:
            p.kill()
            p.wait()


@pytest.fixture(scope="module")
def dask_scheduler(tmp_path_factory):
    from distributed import Client

    d = tmp_path_factory.mktemp("dask")
    log = open(d / "dask.log", "w")
    info = d / "scheduler.json"
    scheduler = _dask_cli("scheduler", "--host", "127.0.0.1", "--port", "0", "--dashboard-address", ":0",
                          "--scheduler-file", str(info), log=log)
    workers = []
    try:
        deadline = time.monotonic() + 60
        while not info.exists() and time.monotonic() < deadline and scheduler.poll() is None:
            time.sleep(0.1)
        address = json.loads(info.read_text())["address"]
        assert address.startswith("tcp://127.0.0.1:")
        workers = [_dask_cli("worker", address, "--nthreads", "1", "--no-nanny", "--no-dashboard",
                             "--local-directory", str(d / f"w{i}"), log=log) for i in range(2)]
        with Client(address, set_as_default=False) as c:
            c.wait_for_workers(2, timeout=60)
        yield address
    finally:
        _stop(workers)
        _stop([scheduler])
        log.close()


def test_dask_scheduler_address_is_byte_identical(local, sweep_file, dask_scheduler, tmp_path):
    out, _ = local
    s = run_sweep(sweep_file, str(tmp_path / "tcp"), scheduler=dask_scheduler, quiet=True)
    assert s["points"] == 16 and s["ran"] == 16 and s["failed"] == 0
    assert files(str(tmp_path / "tcp")) == files(out)


def test_cli_sweep_on_a_dask_scheduler_address(local, sweep_file, dask_scheduler, tmp_path):
    out, _ = local
    r = subprocess.run([os.environ["CLEARSHAPE_CLI"], "sweep", str(sweep_file), "--out", str(tmp_path / "cli"),
                        "--scheduler", dask_scheduler], capture_output=True, text=True, timeout=240)
    assert r.returncode == 0, r.stderr
    assert "16/16 points (0 failed)" in r.stderr and "No clients found" not in r.stderr
    assert files(str(tmp_path / "cli")) == files(out)


def test_an_unreachable_scheduler_exits_1_naming_it(sweep_file, tmp_path):
    """Errors from distributed exit 1; 2 is kept for a bad sweep file (docs/sweeps.md)."""
    import socket

    with socket.socket() as s:  # a port nobody listens on
        s.bind(("127.0.0.1", 0))
        address = f"tcp://127.0.0.1:{s.getsockname()[1]}"
    env = dict(os.environ, DASK_DISTRIBUTED__COMM__TIMEOUTS__CONNECT="2s")
    r = subprocess.run([os.environ["CLEARSHAPE_CLI"], "sweep", str(sweep_file), "--out", str(tmp_path / "x"),
                        "--scheduler", address, "--quiet"], capture_output=True, text=True, timeout=120, env=env)
    assert r.returncode == 1, r.stderr
    assert f"--scheduler {address}: " in r.stderr and "Traceback" not in r.stderr
    assert not list((tmp_path / "x" / ".sweep").iterdir())  # nothing was stored


# Issue 23: without matplotlib a sweep with `plot = [...]` ran every point, then died with a
# raw ModuleNotFoundError. The imports a sweep needs are checked before any point runs (exit 1,
# naming the Debian package); without `plot` matplotlib is not needed at all.
def test_a_missing_matplotlib_is_named_before_any_point_runs(sweep_file, tmp_path):
    fake = tmp_path / "no_matplotlib" / "matplotlib"
    fake.mkdir(parents=True)
    (fake / "__init__.py").write_text("raise ImportError(\"No module named 'matplotlib'\", name='matplotlib')\n")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(fake.parent), os.environ.get("PYTHONPATH", "")]))
    run = [sys.executable, "-m", "clearshape.sweep", "--quiet", "--workers", "1"]
    r = subprocess.run([*run, str(sweep_file), "--out", str(tmp_path / "plot")], capture_output=True, text=True,
                       env=env, timeout=60)
    assert r.returncode == 1, r.stderr
    assert "matplotlib is missing" in r.stderr and "install Debian's python3-matplotlib" in r.stderr
    assert "Traceback" not in r.stderr and not (tmp_path / "plot").exists()
    unplotted = tmp_path / "unplotted.toml"
    unplotted.write_text(SWEEP.replace('plot = ["frequency_error", "contact_damping"]\n', "")
                         .replace("samples = 2", "samples = 1"))
    r = subprocess.run([*run, str(unplotted), "--out", str(tmp_path / "table")], capture_output=True, text=True,
                       env=env, timeout=120)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "table" / "results.h5").exists() and not (tmp_path / "table" / "improvement_map.png").exists()
