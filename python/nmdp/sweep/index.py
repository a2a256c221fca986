"""The sweep's index: one row per run, written to DIR/index.csv and DIR/index.h5 (one dataset per
column), each atomically (a temporary file renamed), so a reader sees the old index or the new.

Columns: id, one per override key any run sets (empty where a run does not set it), status
("complete" or "failed: why"), file (relative to DIR; empty for a failed run), the final base
position x, y, z (/base/position's last row), the final yaw (/base/rpy), the wall time (the sum of
/stats/wall_time; a failed run's subprocess time) and the mean outer iterations of the steps (the
rows after the initial state).
"""
import csv
import json
import math
import os

import h5py
import numpy as np

METRICS = ("x", "y", "z", "yaw", "wall_time", "mean_outer_iterations")


def file_status(path):
    """A run file's /status ("complete", "failed: ...", ...), or None if it is absent or unreadable."""
    try:
        with h5py.File(path, "r") as f:
            s = f["status"][()]
    except (OSError, KeyError):
        return None
    return (s.decode("utf-8", "replace") if isinstance(s, bytes) else str(s)).rstrip("\0").strip()


def is_complete(path):
    return file_status(path) == "complete"


def metrics(path):
    """The summary metrics of a complete run file (dict of METRICS)."""
    with h5py.File(path, "r") as f:
        rows = int(f["rows"][()]) if "rows" in f else int(f["steps"][()])  # older files counted rows in /steps
        position = f["base/position"][rows - 1]
        yaw = f["base/rpy"][rows - 1, 2]
        wall = float(np.sum(f["stats/wall_time"][:rows]))
        outer = f["stats/outer_iterations"][1:rows]
    return dict(x=float(position[0]), y=float(position[1]), z=float(position[2]), yaw=float(yaw), wall_time=wall,
                mean_outer_iterations=float(np.mean(outer)) if len(outer) else math.nan)


def rows(sweep_runs, results, out_dir):
    """One row per run (in the sweep's order): results[id] is the task's result for a run made now,
    absent for a run found complete; a complete run's metrics are read from its file."""
    keys = list(dict.fromkeys(k for r in sweep_runs for k in r.overrides))
    out = []
    for run in sweep_runs:
        path = os.path.join(out_dir, "runs", run.id + ".h5")
        result = results.get(run.id)
        status = result["status"] if result else "complete"
        row = {"id": run.id}
        row.update({k: run.overrides.get(k) for k in keys})
        row.update(status=status, file="")
        row.update({m: math.nan for m in METRICS})
        if status == "complete":
            row["file"] = os.path.relpath(path, out_dir)
            try:
                row.update(metrics(path))
            except (OSError, KeyError, ValueError, IndexError) as e:
                row["status"] = f"failed: {row['file']} is unreadable ({e})"
                row["file"] = ""
        elif result:
            row["wall_time"] = result["wall"]
        out.append(row)
    return keys, out


def _cell(value):
    """A CSV cell: a string as it is, a number in full precision, anything else as JSON; None empty."""
    if value is None:
        return ""
    if isinstance(value, str):
        return value
    if isinstance(value, float):
        return "" if math.isnan(value) else repr(value)
    return json.dumps(value, separators=(",", ":"))


def write_csv(path, columns, table):
    tmp = path + ".tmp"
    with open(tmp, "w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        w.writerow(columns)
        for row in table:
            w.writerow([_cell(row[c]) for c in columns])
    os.replace(tmp, path)


def _column_array(values):
    """Numbers (bools, ints, floats, None as NaN) as float64 when every value is one; else UTF-8
    strings as the CSV has them."""
    numeric = all(v is None or (isinstance(v, (int, float)) and not isinstance(v, bool)) for v in values)
    if numeric:
        return np.array([math.nan if v is None else float(v) for v in values], dtype=np.float64)
    return np.array([_cell(v) for v in values], dtype=h5py.string_dtype("utf-8"))


def dataset_name(column):
    """A column's dataset in index.h5: its name, a "/" (which would make a group) written %2F."""
    return column.replace("/", "%2F")


def write_h5(path, columns, table):
    tmp = path + ".tmp"
    with h5py.File(tmp, "w") as f:
        for c in columns:
            f.create_dataset(dataset_name(c), data=_column_array([row[c] for row in table]))
        f.attrs["columns"] = json.dumps(columns)
    os.replace(tmp, path)


def write(out_dir, sweep_runs, results):
    """Writes DIR/index.csv and DIR/index.h5; returns the rows."""
    keys, table = rows(sweep_runs, results, out_dir)
    columns = ["id", *keys, "status", "file", *METRICS]
    write_csv(os.path.join(out_dir, "index.csv"), columns, table)
    write_h5(os.path.join(out_dir, "index.h5"), columns, table)
    return table
