"""Sweep results on disk (docs/sweeps.md). Every write is atomic (temporary file, fsync, rename).

  DIR/.sweep/batch-NNNNNN.json  finished batches (resume: a rerun keeps them, does the rest)
  DIR/results.h5                one row per point; HDF5 with fixed attributes and no
                                timestamps, so the same sweep gives the same bytes
  DIR/results.csv, results.json the same table for spreadsheets, pandas and MATLAB
"""
import json
import math
import os
import tempfile

import numpy as np

from .sweep_run import METRICS
from .sweep_spec import PARAMETERS

COLUMNS = ["index", "seed", *PARAMETERS, "status", *METRICS]
STATE = ".sweep"


def _umask():
    """The process's umask, read without changing it (Linux /proc; else set and restored)."""
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except OSError:
        pass
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _new_file_mode(fd):
    """mkstemp creates 0600; a result is a file like any other: 0666 less the umask (0644 under 022)."""
    os.fchmod(fd, 0o666 & ~_umask())


def write_atomic(path, data):
    """Writes bytes to path through a temporary file in the same folder (mode as open() gives)."""
    folder = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=".tmp-", suffix=".part")
    try:
        _new_file_mode(fd)
        with os.fdopen(fd, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


OUTPUTS = ("results.h5", "results.csv", "results.json", "improvement_map.png")


def refuse_input_as_output(input_path, out):
    """Inputs are never outputs: raises ValueError when the sweep file is one of the results."""
    if not os.path.exists(input_path):
        return
    for name in OUTPUTS:
        target = os.path.join(out, name)
        if os.path.exists(target) and os.path.samefile(input_path, target):
            raise ValueError(f"{input_path}: the sweep file is also the output {target}; choose another --out")


def batch_path(out, batch_id):
    return os.path.join(out, STATE, f"batch-{batch_id:06d}.json")


def save_batch(out, digest, batch_id, results):
    doc = {"digest": digest, "batch": batch_id, "results": results}
    write_atomic(batch_path(out, batch_id), json.dumps(doc).encode())


def load_batches(out, digest):
    """Finished batches {id: results} of this sweep; raises ValueError for another sweep's state."""
    folder = os.path.join(out, STATE)
    done = {}
    if not os.path.isdir(folder):
        return done
    for name in sorted(os.listdir(folder)):
        path = os.path.join(folder, name)
        if name.startswith(".tmp-"):
            os.unlink(path)  # a killed run's temporary
            continue
        if not (name.startswith("batch-") and name.endswith(".json")):
            continue
        with open(path) as f:
            doc = json.load(f)
        if doc.get("digest") != digest:
            raise ValueError(f"{out}: holds results of a different sweep (digest {str(doc.get('digest'))[:12]}…); "
                             "choose another --out or pass --fresh to remove them")
        done[doc["batch"]] = doc["results"]
    return done


def remove_own_files(out):
    """--fresh: removes only what a sweep writes (the state folder and the three results files)."""
    folder = os.path.join(out, STATE)
    if os.path.isdir(folder):
        for name in os.listdir(folder):
            if name.startswith(("batch-", ".tmp-")):
                os.unlink(os.path.join(folder, name))
        os.rmdir(folder)
    for name in OUTPUTS:
        if os.path.exists(os.path.join(out, name)):
            os.unlink(os.path.join(out, name))


def table(points, results):
    """Rows (dicts) in point order: the point's parameters and its metrics."""
    by_index = {r["index"]: r for r in results}
    rows = []
    for p in points:
        r = by_index[p["index"]]
        row = {"index": p["index"], "seed": p["seed"]}
        for k in PARAMETERS:
            row[k] = math.nan if p[k] is None else p[k]
        row["status"] = r["status"]
        for k in METRICS:
            row[k] = float(r[k])
        rows.append(row)
    return rows


def _column(rows, name):
    values = [r[name] for r in rows]
    if name in ("index", "seed"):
        return np.array(values, dtype=np.int64)
    if values and isinstance(values[0], str):
        return np.array([v.encode() for v in values], dtype=f"S{max(1, max(len(v.encode()) for v in values))}")
    return np.array(values, dtype=np.float64)


def write_hdf5(path, rows, attributes):
    """One dataset per column under /points, fixed attributes; deterministic bytes."""
    import h5py

    folder = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=".tmp-", suffix=".h5")
    _new_file_mode(fd)
    os.close(fd)
    try:
        # No object timestamps anywhere (root group, group, datasets) and a fixed file format:
        # the same rows give the same bytes.
        fcpl = h5py.h5p.create(h5py.h5p.FILE_CREATE)
        fcpl.set_obj_track_times(False)
        fapl = h5py.h5p.create(h5py.h5p.FILE_ACCESS)
        fapl.set_libver_bounds(h5py.h5f.LIBVER_V110, h5py.h5f.LIBVER_V110)
        fid = h5py.h5f.create(tmp.encode(), h5py.h5f.ACC_TRUNC, fcpl=fcpl, fapl=fapl)
        with h5py.File(fid) as f:
            gcpl = h5py.h5p.create(h5py.h5p.GROUP_CREATE)
            gcpl.set_obj_track_times(False)
            g = h5py.Group(h5py.h5g.create(f.id, b"points", gcpl=gcpl))
            for name in COLUMNS:
                g.create_dataset(name, data=_column(rows, name), track_times=False)
            for key, value in attributes.items():
                f.attrs[key] = value
            f.attrs["columns"] = np.array([c.encode() for c in COLUMNS])
        with open(tmp, "rb") as f:
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def _csv_value(v):
    if isinstance(v, str):
        return '"' + v.replace('"', '""') + '"' if ("," in v or '"' in v) else v
    if isinstance(v, float):
        return "nan" if math.isnan(v) else repr(v)
    return str(v)


def write_csv(path, rows):
    lines = [",".join(COLUMNS)] + [",".join(_csv_value(r[c]) for c in COLUMNS) for r in rows]
    write_atomic(path, ("\n".join(lines) + "\n").encode())


def write_json(path, rows, header):
    def clean(v):
        return None if isinstance(v, float) and math.isnan(v) else v
    doc = dict(header)
    doc["columns"] = COLUMNS
    doc["points"] = [{c: clean(r[c]) for c in COLUMNS} for r in rows]
    write_atomic(path, (json.dumps(doc, indent=1) + "\n").encode())
