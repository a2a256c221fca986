"""`nmdp sweep` on a LocalCluster: every run's file and an index whose rows match the files; a run
equal bit for bit to `nmdp simulate` by hand with the same --set; a re-run that runs nothing; a
failing run reported in the index with exit 4 and no partial file left."""
import csv
import json
import os
import subprocess

import h5py
import numpy as np
import pytest

from conftest import NMDP_BINARY, scene_path
from nmdp.sweep import index, spec

SCENE = scene_path("quadruped_trot_sand.json")
BASE = {"duration": 0.2}
GRID = {"integrator.dt": [0.02, 0.05], "controller.gait.period": [0.4, 0.5]}
LISTED = [{"integrator.method": "ne-pgm"}, {"integrator.method": "pbd-zopgm", "integrator.dt": 0.04}]


def sweep(tmp_path, content, out, *args):
    path = tmp_path / "sweep.json"
    path.write_text(json.dumps(content))
    p = subprocess.run([NMDP_BINARY, "sweep", str(path), "--out", str(out), "--workers", "2", *args],
                       capture_output=True, text=True, timeout=120)
    return p, spec.load(str(path))


def read_index(out):
    with open(out / "index.csv", newline="") as f:
        return list(csv.DictReader(f))


@pytest.fixture(scope="module")
def finished(tmp_path_factory):
    """A sweep of 6 runs (4 grid points and 2 listed runs), made once for the tests below."""
    tmp = tmp_path_factory.mktemp("sweep")
    out = tmp / "out"
    p, s = sweep(tmp, {"scene": SCENE, "base": BASE, "grid": GRID, "runs": LISTED}, out)
    assert p.returncode == 0, p.stderr
    return tmp, out, s, p


def test_every_run_has_its_file_and_an_index_row_that_matches_it(finished):
    _, out, s, p = finished
    assert "0 runs already complete, 6 to run" in p.stderr
    assert sorted(os.listdir(out / "runs")) == sorted(r.id + ".h5" for r in s.runs)
    rows = read_index(out)
    assert list(rows[0]) == ["id", "duration", "integrator.dt", "controller.gait.period", "integrator.method",
                             "status", "file", "x", "y", "z", "yaw", "wall_time", "mean_outer_iterations"]
    assert [row["id"] for row in rows] == [r.id for r in s.runs]
    for row, run in zip(rows, s.runs):
        assert row["status"] == "complete" and row["file"] == f"runs/{run.id}.h5"
        for key in s.keys():
            assert row[key] == ("" if key not in run.overrides else index._cell(run.overrides[key]))
        with h5py.File(out / row["file"], "r") as f:
            assert f["status"][()].rstrip(b"\0") == b"complete"
            steps = int(f["rows"][()])
            assert float(row["x"]) == f["base/position"][steps - 1, 0]
            assert float(row["z"]) == f["base/position"][steps - 1, 2]
            assert float(row["yaw"]) == f["base/rpy"][steps - 1, 2]
            assert float(row["wall_time"]) == pytest.approx(np.sum(f["stats/wall_time"][:steps]), rel=1e-12)
            assert float(row["mean_outer_iterations"]) == pytest.approx(np.mean(f["stats/outer_iterations"][1:steps]))
            assert f["base/position"][steps - 1, 0] != 0  # the robot moved: the comparison above means something


def test_the_hdf5_index_has_the_csvs_columns_and_values(finished):
    _, out, s, _ = finished
    rows = read_index(out)
    with h5py.File(out / "index.h5", "r") as f:
        columns = json.loads(f.attrs["columns"])
        assert columns == list(rows[0])
        assert [v.decode() for v in f["id"][()]] == [row["id"] for row in rows]
        assert [v.decode() for v in f["status"][()]] == ["complete"] * 6
        np.testing.assert_array_equal(f["x"][()], [float(row["x"]) for row in rows])
        dt = f["integrator.dt"][()]
        assert dt.dtype == np.float64 and list(dt[:4]) == [0.02, 0.02, 0.05, 0.05] and np.isnan(dt[4]) and dt[5] == 0.04


def test_a_sweep_run_equals_nmdp_simulate_by_hand_bit_for_bit(finished):
    tmp, out, s, _ = finished
    run = s.runs[5]  # a string value and numbers, as a user types them
    by_hand = tmp / "by_hand.h5"
    subprocess.run([NMDP_BINARY, "simulate", SCENE, "--set", "duration=0.2", "--set", "integrator.method=pbd-zopgm",
                    "--set", "integrator.dt=0.04", "--out", str(by_hand), "--quiet"], check=True, timeout=60)
    with h5py.File(by_hand, "r") as a, h5py.File(out / "runs" / f"{run.id}.h5", "r") as b:
        assert a["q"].shape == b["q"].shape == (6, 15)  # 0.2 s of 0.04 s steps; a planar base
        assert a["q"][()].tobytes() == b["q"][()].tobytes()
        assert a["qdot"][()].tobytes() == b["qdot"][()].tobytes()


def test_a_rerun_of_a_finished_sweep_runs_nothing(finished):
    tmp, out, s, _ = finished
    files = [out / "runs" / f"{r.id}.h5" for r in s.runs]
    before = [f.stat().st_mtime_ns for f in files]
    index_before = read_index(out)
    p, _ = sweep(tmp, {"scene": SCENE, "base": BASE, "grid": GRID, "runs": LISTED}, out)
    assert p.returncode == 0, p.stderr
    assert "6 runs already complete, 0 to run" in p.stderr
    assert "LocalCluster" not in p.stderr  # no cluster was even started
    assert [f.stat().st_mtime_ns for f in files] == before
    assert read_index(out) == index_before


def test_a_rerun_with_more_runs_makes_only_the_new_ones_and_indexes_all(finished, tmp_path):
    _, out, s, _ = finished
    copy = tmp_path / "out"
    subprocess.run(["cp", "-a", str(out), str(copy)], check=True)
    before = {r.id: (copy / "runs" / f"{r.id}.h5").stat().st_mtime_ns for r in s.runs}
    p, s2 = sweep(tmp_path, {"scene": SCENE, "base": BASE, "grid": GRID, "runs": LISTED + [{"controller.kd": 2}]},
                  copy, "--quiet")
    assert p.returncode == 0 and p.stderr == "" and p.stdout == "", p.stderr
    assert {r.id: (copy / "runs" / f"{r.id}.h5").stat().st_mtime_ns for r in s.runs} == before
    rows = read_index(copy)
    assert [row["id"] for row in rows] == [r.id for r in s2.runs] and len(rows) == 7
    assert rows[6]["controller.kd"] == "2" and rows[6]["status"] == "complete"


def test_failing_runs_are_failed_in_the_index_with_exit_4_and_no_partial_file(tmp_path):
    out = tmp_path / "out"
    # One outer iteration fails the first step after the file exists (exit 4); dt = 2 s passes the
    # key check (the first run, with dt 0.05, is the one checked) but not the scene's range (exit 1).
    p, s = sweep(tmp_path, {"scene": SCENE, "base": {"duration": 0.1, "integrator.adaptive": False, "integrator.dt": 0.05},
                            "grid": {"integrator.max_outer_iterations": [100, 1]}, "runs": [{"integrator.dt": 2}]}, out)
    assert p.returncode == 4, p.stderr
    rows = read_index(out)
    assert rows[0]["status"] == "complete"
    assert rows[1]["status"] == ("failed: nmdp simulate: step 1 (from t = 0 s) failed: outer-iteration limit reached "
                                 "at the smallest sub-step 1e-05 s")  # not "<the deleted file> keeps ..."
    assert rows[2]["status"].startswith("failed: nmdp simulate: error: ")
    assert "integrator.dt: must be in [1e-06, 1], got 2" in rows[2]["status"]
    for row in rows[1:]:
        assert row["file"] == "" and row["x"] == "" and float(row["wall_time"]) > 0
    assert os.listdir(out / "runs") == [f"{s.runs[0].id}.h5"]  # no partial file of the failed runs
    assert f"run {s.runs[2].id} (duration=0.1 integrator.adaptive=false integrator.dt=2): failed: " in p.stderr
    assert "3 runs, 1 complete, 2 failed" in p.stdout
