"""Sweeps over rig truths, commands and shapers (docs/sweeps.md), locally or on a Dask cluster.

    python3 -m clearshape.sweep SWEEP.toml --out DIR [--scheduler tcp://HOST:8786] [--workers N]
    clearshape sweep SWEEP.toml --out DIR …            (the CLI runs this module)

    >>> from clearshape.sweep import run_sweep
    >>> summary = run_sweep("SWEEP.toml", "out/sweep")            # every core of this machine
    >>> summary = run_sweep("SWEEP.toml", "out/sweep", scheduler="tcp://head:8786")

Points are batched into tasks; each task evaluates its points with the bindings. Finished
batches are stored as they arrive, so an interrupted sweep resumes where it stopped and ends
with the same bytes as a fresh run. A point that fails is kept with its reason (status column);
a task that fails is retried (Dask: `retries`) and, if it still fails, left for the next run.
"""
import argparse
import concurrent.futures
import ctypes
import os
import signal
import sys
import time

from . import _core
from .sweep_run import run_batch
from .sweep_spec import MAX_POINTS, Sweep, SweepError
from . import sweep_store as store


class Progress:
    """One line on stderr per finished task: points done, failed points, points per second."""

    def __init__(self, total, done, quiet):
        self.total, self.done, self.failed, self.quiet = total, done, 0, quiet
        self.start, self.fresh = time.monotonic(), 0

    def add(self, results):
        self.done += len(results)
        self.fresh += len(results)
        self.failed += sum(r["status"] != "ok" for r in results)
        if not self.quiet:
            rate = self.fresh / max(1e-9, time.monotonic() - self.start)
            print(f"clearshape sweep: {self.done}/{self.total} points ({self.failed} failed) "
                  f"{rate:.2f} points/s", file=sys.stderr, flush=True)


def _batches(points, size):
    return [points[i:i + size] for i in range(0, len(points), size)]


_PR_SET_PDEATHSIG = 1  # linux/prctl.h


def _die_with_parent(parent_pid):
    """Pool-worker initializer: the kernel sends the worker SIGKILL when its parent dies (SIGTERM,
    kill -9), so no worker keeps computing under PID 1; a parent already gone ends it at once."""
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
    except (OSError, AttributeError):  # not Linux: the parent's SIGTERM handler still ends the pool
        pass
    if os.getppid() != parent_pid:
        os._exit(1)
    # SIGINT (Ctrl-C reaches the whole process group) is the parent's to handle.
    signal.signal(signal.SIGINT, signal.SIG_IGN)


class _Terminated(BaseException):
    """SIGTERM/SIGHUP reached the sweep: the pool is shut down and its workers ended (a
    BaseException, like KeyboardInterrupt, so no `except Exception` swallows it)."""

    def __init__(self, signo):
        super().__init__(f"ended by {signal.Signals(signo).name}")
        self.signo = signo


def _raise_terminated(signo, _frame):
    raise _Terminated(signo)


def _run_local(pending, settings, workers, on_done, fn):
    if workers == 1:
        for bid, batch in pending:
            on_done(bid, fn(batch, settings))
        return []
    with concurrent.futures.ProcessPoolExecutor(max_workers=workers, initializer=_die_with_parent,
                                                initargs=(os.getpid(),)) as pool:
        try:
            return _collect(pool, pending, settings, on_done, fn)
        except BaseException:
            # SIGTERM, Ctrl-C or a failed store: no batch is left running in the background.
            for process in list((pool._processes or {}).values()):  # noqa: SLF001 — no public handle
                process.kill()
            pool.shutdown(wait=True, cancel_futures=True)
            raise


def _collect(pool, pending, settings, on_done, fn):
    futures = {pool.submit(fn, batch, settings): bid for bid, batch in pending}
    lost = []
    for f in concurrent.futures.as_completed(futures):
        try:
            on_done(futures[f], f.result())
        except Exception as e:  # noqa: BLE001 — a dead worker: the batch stays for the next run
            lost.append((futures[f], repr(e)))
    return lost


class DaskError(RuntimeError):
    """The Dask scheduler could not be reached or failed (exit 1: exit 2 is a bad sweep file)."""


def _connect(scheduler):
    from distributed import Client

    try:
        return Client(scheduler, set_as_default=False)
    except Exception as e:  # noqa: BLE001 — OSError (timeout), ValueError (bad address), …
        raise DaskError(f"--scheduler {scheduler}: {type(e).__name__}: {e}") from e


def _run_dask(pending, settings, scheduler, retries, digest, on_done, fn):
    from distributed import Client, as_completed

    own = not isinstance(scheduler, Client)
    client = _connect(scheduler) if own else scheduler
    where = scheduler if own else getattr(client.scheduler, "address", "of the given Client")
    lost = []
    try:
        futures = {client.submit(fn, batch, settings, retries=retries, pure=False,
                                 key=f"clearshape-sweep-{digest[:12]}-{bid}"): bid for bid, batch in pending}
        # The client's own loop: a Client made with set_as_default=False is no default client,
        # and as_completed without a loop looks for one ("No clients found", issue 23).
        for f in as_completed(futures, loop=client.loop):
            try:
                on_done(futures[f], f.result())
            except Exception as e:  # noqa: BLE001 — failed after its retries
                lost.append((futures[f], repr(e)))
        return lost
    except Exception as e:  # noqa: BLE001 — the scheduler, not a task (those are in `lost`)
        raise DaskError(f"--scheduler {where}: {type(e).__name__}: {e}") from e
    finally:
        if own:
            client.close()


class MissingDependency(RuntimeError):
    """A Python package the sweep needs is not installed (exit 1), found before any point runs."""


_DEBIAN = {"h5py": "python3-h5py", "matplotlib": "python3-matplotlib", "distributed": "python3-distributed"}


def _check_imports(settings, scheduler):
    """h5py always (results.h5), matplotlib when `plot` is set, distributed for an address."""
    import importlib

    needed = ["h5py"] + (["matplotlib"] if settings["plot"] else []) + (
        ["distributed"] if isinstance(scheduler, str) else [])
    for name in needed:
        try:
            importlib.import_module(name)
        except ImportError as e:
            why = {"h5py": "results.h5", "matplotlib": f"plot = {list(settings['plot'])}: improvement_map.png",
                   "distributed": f"--scheduler {scheduler}"}[name]
            raise MissingDependency(f"{name} is missing ({e}); it is needed for {why}: install Debian's "
                                    f"{_DEBIAN[name]}") from e


def run_sweep(sweep, out, scheduler=None, workers=None, retries=2, fresh=False, quiet=False,
              batch_function=run_batch, max_points=MAX_POINTS):
    """Runs (or resumes) a sweep into folder `out`; returns a summary dict.

    sweep: a path to SWEEP.toml or a Sweep. scheduler: None (this machine, `workers` processes,
    default every core), a Dask scheduler address 'tcp://HOST:8786' or a distributed.Client.
    batch_function(points, settings) evaluates one task (default sweep_run.run_batch; the tests
    pass one that fails to exercise the retries). Raises SweepError (a ValueError) for a bad
    sweep file, RuntimeError when tasks still failed after their retries (their points are
    kept for the next run), DaskError (a RuntimeError) when the scheduler cannot be reached
    or fails, and MissingDependency (a RuntimeError) before any point runs when h5py, matplotlib
    (`plot` set) or distributed (an address) is not installed. A sweep of more than `max_points` points is refused (SweepError, with
    its estimate) before the output folder is made.
    """
    if not isinstance(sweep, Sweep):
        sweep = Sweep.load(sweep)
    sweep.check_size(max_points)
    _check_imports(sweep.settings, scheduler)
    if not quiet:
        print(f"clearshape sweep: {sweep.describe_estimate()}", file=sys.stderr, flush=True)
    store.refuse_input_as_output(sweep.path, out)
    os.makedirs(os.path.join(out, store.STATE), exist_ok=True)
    if fresh:
        store.remove_own_files(out)
        os.makedirs(os.path.join(out, store.STATE), exist_ok=True)
    digest = sweep.digest()
    settings = sweep.settings
    points = sweep.points()
    batches = _batches(points, settings["batch"])
    done = store.load_batches(out, digest)
    pending = [(bid, b) for bid, b in enumerate(batches) if bid not in done]
    progress = Progress(len(points), sum(len(batches[b]) for b in done if b < len(batches)), quiet)
    t0 = time.monotonic()

    def on_done(bid, results):
        store.save_batch(out, digest, bid, results)
        done[bid] = results
        progress.add(results)

    if scheduler is None:
        lost = _run_local(pending, settings, workers or os.cpu_count() or 1, on_done, batch_function)
    else:
        lost = _run_dask(pending, settings, scheduler, retries, digest, on_done, batch_function)
    wall_s = time.monotonic() - t0
    if lost:
        first = lost[0]
        raise RuntimeError(f"{len(lost)} task(s) failed after their retries (batch {first[0]}: {first[1]}); "
                           f"their points are not lost: rerun the same command to do them")
    results = [r for bid in sorted(done) for r in done[bid]]
    rows = store.table(points, results)
    attributes = {"schema_version": 1, "clearshape_version": _core.__version__, "sweep_digest": digest,
                  "sweep_file": sweep.text, "points": len(points)}
    store.write_hdf5(os.path.join(out, "results.h5"), rows, attributes)
    store.write_csv(os.path.join(out, "results.csv"), rows)
    header = {"schema_version": 1, "clearshape_version": _core.__version__, "sweep_digest": digest,
              "settings": settings, "axes": sweep.axes()}
    store.write_json(os.path.join(out, "results.json"), rows, header)
    if settings["plot"]:
        from .sweep_plot import plot_png

        x, y = settings["plot"]
        try:
            png = plot_png(rows, x, y, f"mean improvement over {x} × {y} ({len(points)} points)")
            store.write_atomic(os.path.join(out, "improvement_map.png"), png)
        except ValueError as e:  # no successful point: the table is still written
            print(f"clearshape sweep: no improvement map: {e}", file=sys.stderr)
    failed = [r for r in rows if r["status"] != "ok"]
    return {"points": len(points), "ran": progress.fresh,
            "failed": len(failed), "failures": [(r["index"], r["status"]) for r in failed],
            "wall_s": wall_s, "out": out}


def main(argv=None):
    ap = argparse.ArgumentParser(prog="clearshape sweep", description=__doc__.split("\n")[0])
    ap.add_argument("sweep", help="the sweep file (TOML, docs/sweeps.md)")
    ap.add_argument("--out", required=True, help="output folder (results.h5, results.csv, results.json)")
    ap.add_argument("--scheduler", help="Dask scheduler address, e.g. tcp://HOST:8786 (default: this machine)")
    ap.add_argument("--workers", type=int, help="local worker processes (default: every core)")
    ap.add_argument("--retries", type=int, default=2, help="Dask: retries of a failed task (default 2)")
    ap.add_argument("--fresh", action="store_true", help="remove this folder's earlier sweep results first")
    ap.add_argument("--quiet", action="store_true", help="no progress lines on stderr")
    ap.add_argument("--max-points", type=int, default=MAX_POINTS,
                    help=f"refuse a sweep of more points than this (default {MAX_POINTS:,}: about 2 GB)")
    a = ap.parse_args(argv)
    if a.max_points < 1:
        ap.error(f"--max-points = {a.max_points} is out of range; allowed: >= 1")
    if os.path.exists(a.out) and not os.path.isdir(a.out):
        print(f"clearshape sweep: error: --out {a.out} is a file, not a folder; give a folder "
              f"(created if missing) for results.h5, results.csv and results.json", file=sys.stderr)
        return 2
    if a.workers is not None and not 1 <= a.workers <= 4096:
        ap.error(f"--workers = {a.workers} is out of range; allowed: [1, 4096]")
    if not 0 <= a.retries <= 100:
        ap.error(f"--retries = {a.retries} is out of range; allowed: [0, 100]")
    if a.scheduler is not None and not a.scheduler.startswith(("tcp://", "tls://", "inproc://", "ucx://")):
        ap.error(f"--scheduler = {a.scheduler} must be an address such as tcp://HOST:8786")
    for signo in (signal.SIGTERM, signal.SIGHUP):  # end the pool's workers too, then exit by the signal
        signal.signal(signo, _raise_terminated)
    try:
        s = run_sweep(a.sweep, a.out, a.scheduler, a.workers, a.retries, a.fresh, a.quiet,
                      max_points=a.max_points)
    except _Terminated as e:
        print(f"clearshape sweep: {e}; finished batches are kept (rerun to resume)", file=sys.stderr)
        signal.signal(e.signo, signal.SIG_DFL)
        os.kill(os.getpid(), e.signo)
        return 128 + e.signo
    except (SweepError, ValueError, FileNotFoundError, IsADirectoryError) as e:
        print(f"clearshape sweep: error: {e}", file=sys.stderr)
        return 2
    except (RuntimeError, OSError) as e:
        print(f"clearshape sweep: error: {e}", file=sys.stderr)
        return 1
    for index, status in s["failures"][:20]:
        print(f"clearshape sweep: point {index} {status}", file=sys.stderr)
    print(f"points {s['points']}  failed {s['failed']}  wall {s['wall_s']:.2f} s  -> {a.out}/results.h5")
    return 0


if __name__ == "__main__":
    sys.exit(main())
