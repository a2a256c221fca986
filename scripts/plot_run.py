#!/usr/bin/python3
"""Plots a run written by `nmdp simulate --out OUT.h5`: torso height and forward distance against time.

Usage:  scripts/plot_run.py OUT.h5 PLOT.png
Needs Debian's python3-h5py and python3-matplotlib (scripts/install-deps.sh), hence /usr/bin/python3.

Reads the layout of README "Usage" (src/sim/trajectory_writer.hpp): /rows (the number of complete
rows, the first at t = 0), /steps (the time steps they cover), /time, /base/position (x 3), /status
if present, and the root attribute `config`
(the resolved scene as JSON), which gives the title (robot, contact model, integrator method, dt)
and the standing height robot.initial.height (drawn dashed, with a band of +-30 % around it) when
it parses. The summary line gives the forward distance and the torso height range.
Only the first /rows rows are used: a run that ended has exactly that many, a killed run keeps up
to a chunk of NaN rows after them. A killed run's file is still marked by its SWMR writer and is
opened as a SWMR reader (h5py swmr=True). Older files without /rows counted rows in /steps; files
without either use len(/time).
Exits with status 1 and a one-line message when the file is missing, not HDF5, or lacks the data.
"""
import json
import os
import sys


def fail(message):
    sys.exit(f"plot_run.py: error: {message}")


def text(value):
    """An HDF5 string (bytes, str, or a 0-d array of either) as str, without trailing NULs."""
    if getattr(value, "shape", None) == () and hasattr(value, "item"):
        value = value.item()  # a numpy 0-d array or scalar
    if isinstance(value, bytes):
        value = value.decode("utf-8", errors="replace")
    return str(value).rstrip("\0").strip()


def read_run(path):
    """Returns (time, base_position, status or None, config dict or None, root attributes)."""
    import h5py
    import numpy as np

    if not os.path.exists(path):
        fail(f"{path}: no such file")
    try:
        f = h5py.File(path, "r")
    except OSError:
        try:
            f = h5py.File(path, "r", swmr=True)  # a killed run
        except OSError as e:
            fail(f"{path}: cannot open as HDF5 ({e})")
    with f:
        for name in ("time", "base/position"):
            if name not in f:
                fail(f"{path}: dataset '/{name}' is missing (is this a file written by 'nmdp simulate'?)")
        try:
            stored = len(f["time"])
            counter = "rows" if "rows" in f else "steps" if "steps" in f else None
            rows = int(f[counter][()]) if counter else stored
            if not 0 <= rows <= stored:
                fail(f"{path}: '/{counter}' is {rows}, but '/time' has {stored} rows")
            # Time steps of dt the rows cover; older files (rows in /steps) were written every step.
            steps = int(f["steps"][()]) if counter == "rows" else max(rows - 1, 0)
            time = np.asarray(f["time"][:rows], dtype=float).reshape(-1)
            position = np.asarray(f["base/position"][:rows], dtype=float)
        except (OSError, ValueError, TypeError) as e:
            fail(f"{path}: cannot read '/rows', '/steps', '/time' or '/base/position' ({e})")
        if position.ndim != 2 or position.shape[1] != 3 or position.shape[0] < len(time):
            fail(f"{path}: '/base/position' is {position.shape}, expected at least {len(time)} x 3 rows")
        status = text(f["status"][()]) if "status" in f else None
        attributes = {name: f.attrs[name] for name in f.attrs}
    config = None
    if "config" in attributes:
        try:
            config = json.loads(text(attributes["config"]))
        except (ValueError, TypeError):
            config = None  # a title without it is still a plot
    return time, position[: len(time)], steps, status, config, attributes


def title_for(path, config, attributes, status):
    """'robot, method, dt = ...' from the config (or the writer's extra attributes), plus an unfinished status."""

    def lookup(keys, attribute):
        node = config
        for key in keys:
            if not isinstance(node, dict) or key not in node:
                node = None
                break
            node = node[key]
        if node is None and attribute is not None and attribute in attributes:
            node = attributes[attribute]
            node = node.item() if hasattr(node, "item") else node
            node = text(node) if isinstance(node, (bytes, str)) else node
        return node

    robot = lookup(["robot", "urdf"], "robot")
    model = lookup(["contacts", "model", "type"], "contact_model")
    model_file = lookup(["contacts", "model", "file"], None)
    method = lookup(["integrator", "method"], "method")
    dt = lookup(["integrator", "dt"], "dt")
    parts = []
    if robot:
        parts.append(os.path.splitext(os.path.basename(str(robot)))[0])
    if model:
        name = str(model).split(":")[0]  # the writer's attribute is "type: description"
        parts.append(name + (f" ({os.path.basename(str(model_file).rstrip('/'))})" if model_file else ""))
    if method:
        parts.append(str(method))
    if isinstance(dt, (int, float)):
        parts.append(f"dt = {dt:g} s")
    title = ", ".join(parts) if parts else os.path.basename(path)
    if status and status != "complete":
        title += f"\n[{status}]"
    return title


def main(argv):
    if len(argv) != 3 or argv[1] in ("-h", "--help"):
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2 if len(argv) != 2 else 0
    run_path, png_path = argv[1], argv[2]
    time, position, steps, status, config, attributes = read_run(run_path)
    if len(time) == 0:
        fail(f"{run_path}: the run has no steps (status: {status or 'unknown'})")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, (height_axes, distance_axes) = plt.subplots(2, 1, sharex=True, figsize=(8, 6))
    standing = None
    if isinstance(config, dict):
        initial = config.get("robot", {}).get("initial", {}) if isinstance(config.get("robot"), dict) else {}
        if isinstance(initial, dict) and isinstance(initial.get("height"), (int, float)):
            standing = float(initial["height"])
    if standing is not None:
        height_axes.axhspan(0.7 * standing, 1.3 * standing, color="tab:gray", alpha=0.12, label="standing height ±30 %")
        height_axes.axhline(standing, color="tab:gray", linestyle="--", linewidth=1, label="standing height")
    height_axes.plot(time, position[:, 2], color="tab:blue", label="torso")
    if standing is not None:
        height_axes.legend(loc="upper right", fontsize="small")
    height_axes.set_ylabel("torso height (base z), m")
    height_axes.grid(True, alpha=0.3)
    distance_axes.plot(time, position[:, 0] - position[0, 0], color="tab:orange")
    distance_axes.set_ylabel("forward distance (x - x0), m")
    distance_axes.set_xlabel("time, s")
    distance_axes.grid(True, alpha=0.3)
    figure.suptitle(title_for(run_path, config, attributes, status))
    figure.tight_layout()
    try:
        figure.savefig(png_path, dpi=100)
    except OSError as e:
        fail(f"{png_path}: cannot write ({e})")
    height = f"torso height {position[:, 2].min():.3f} .. {position[:, 2].max():.3f} m"
    if standing is not None:
        height += f" ({position[:, 2].min() / standing:.2f} .. {position[:, 2].max() / standing:.2f} of standing {standing:.3f} m)"
    print(f"wrote {png_path}: {steps} steps ({len(time)} rows), t = {time[0]:g} .. {time[-1]:g} s; "
          f"forward distance {position[-1, 0] - position[0, 0]:+.3f} m; {height}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
