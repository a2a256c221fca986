"""Shared fixtures of the Python tests: where the sources, the shared robots and the nmdp executable
are (ctest sets NMDP_SOURCE_DIR, NMDP_SHARED_DIR and NMDP_BINARY; run by hand, they default to this
checkout, ../shared and build/nmdp), and the CLI run a Python run is compared with."""
import os
import subprocess

import numpy as np
import pytest

SOURCE_DIR = os.environ.get("NMDP_SOURCE_DIR") or os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
SHARED_DIR = os.environ.get("NMDP_SHARED_DIR") or os.path.join(SOURCE_DIR, "..", "shared")
NMDP_BINARY = os.environ.get("NMDP_BINARY") or os.path.join(SOURCE_DIR, "build", "nmdp")

# The prefix `nmdp simulate` puts before an input error's message on stderr (src/app/main.cpp).
CLI_ERROR_PREFIX = "nmdp simulate: error: "


@pytest.fixture
def source_dir():
    return SOURCE_DIR


@pytest.fixture
def nmdp_binary():
    return NMDP_BINARY


def scene_path(name):
    """A scene under models/scenes, e.g. scene_path("quadruped_trot_sand.json")."""
    return os.path.join(SOURCE_DIR, "models", "scenes", name)


def shared_or_skip(*parts):
    """A file under ../shared, or a skip saying it is absent."""
    path = os.path.join(SHARED_DIR, *parts)
    if not os.path.exists(path):
        pytest.skip(f"{path} is absent (../shared is read in place)")
    return path


def set_arguments(overrides):
    """{"duration": 2} as the command line's ["--set", "duration=2"] (values as JSON, strings as typed)."""
    import json
    args = []
    for key, value in overrides.items():
        args += ["--set", f"{key}={value if isinstance(value, str) else json.dumps(value)}"]
    return args


def run_cli(scene, overrides, out=None):
    """`nmdp simulate scene --set ... [--out out] --quiet`: the completed process (stdout, stderr as text)."""
    args = [NMDP_BINARY, "simulate", scene, *set_arguments(overrides), "--quiet"]
    if out is not None:
        args += ["--out", str(out)]
    return subprocess.run(args, capture_output=True, text=True, timeout=600)


def cli_error(scene, overrides, out):
    """The message `nmdp simulate` prints for bad input (it must exit with status 1, writing nothing to out)."""
    done = run_cli(scene, overrides, out=out)
    assert done.returncode == 1, done.stderr
    assert done.stderr.startswith(CLI_ERROR_PREFIX), done.stderr
    return done.stderr[len(CLI_ERROR_PREFIX):].rstrip("\n")


def read_run(path):
    """The rows of an nmdp output file: {"time", "q", "qdot", "wrench", "outer_iterations", ...} as arrays."""
    h5py = pytest.importorskip("h5py")
    with h5py.File(path, "r") as f:
        n = int(f["rows"][()]) if "rows" in f else int(f["steps"][()])
        return {"time": f["time"][:n], "q": f["q"][:n], "qdot": f["qdot"][:n],
                "wrench": f["contacts/wrench"][:n], "contact_names": [s.decode() if isinstance(s, bytes) else s for s in f["contacts/names"][:]],
                "joint_names": [s.decode() if isinstance(s, bytes) else s for s in f["joint_names"][:]],
                "outer_iterations": f["stats/outer_iterations"][:n], "substeps": f["stats/substeps"][:n],
                "status": f["status"][()].split(b"\0")[0].decode()}


def record(sim, steps):
    """Steps sim `steps` times (stopping at a step that fails): time, q, qdot per row, the start first."""
    rows = {"time": [sim.time], "q": [sim.q.copy()], "qdot": [sim.qdot.copy()]}
    for _ in range(steps):
        stats = sim.step()
        if not stats.converged:
            break
        rows["time"].append(sim.time)
        rows["q"].append(sim.q.copy())
        rows["qdot"].append(sim.qdot.copy())
    return {key: np.array(value) for key, value in rows.items()}
