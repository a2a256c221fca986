"""One run as a worker makes it (nmdp.sweep.task.run_one): the file appears under its final name only
when the run completed; a run killed by its timeout or that cannot start leaves no file and says why."""
import os

from conftest import NMDP_BINARY, scene_path
from nmdp.sweep import task

SCENE = scene_path("quadruped_trot_sand.json")


def test_a_complete_run_is_renamed_to_its_file_in_a_folder_made_for_it(tmp_path):
    out = tmp_path / "a" / "b" / "run.h5"
    r = task.run_one(NMDP_BINARY, SCENE, ["duration=0.1"], str(out))
    assert r["status"] == "complete" and r["returncode"] == 0 and r["wall"] > 0
    assert os.listdir(out.parent) == ["run.h5"]
    assert r["cmd"][:4] == [NMDP_BINARY, "simulate", SCENE, "--set"] and r["cmd"][-1] == "--quiet"
    assert r["cmd"][-2].startswith(str(out) + ".part-")


def test_a_run_past_its_timeout_is_killed_and_leaves_no_file(tmp_path):
    out = tmp_path / "run.h5"
    r = task.run_one(NMDP_BINARY, SCENE, ["duration=100", "integrator.dt=0.001"], str(out), timeout=1.5)
    assert r["status"] == "failed: killed after 1.5 s" and r["returncode"] == "timeout"
    assert 1.5 <= r["wall"] < 10
    assert os.listdir(tmp_path) == []


def test_a_binary_that_is_not_there_is_a_failed_run_not_an_exception(tmp_path):
    r = task.run_one(str(tmp_path / "absent"), SCENE, [], str(tmp_path / "run.h5"))
    assert r["status"] == f"failed: {tmp_path}/absent: No such file or directory"
    assert os.listdir(tmp_path) == []
