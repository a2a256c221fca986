"""`nmdp sweep --scheduler` on a cluster of its own: a dask-scheduler and two dask-workers started as
processes on 127.0.0.1, one worker SIGKILLed while it runs a task. The sweep completes with every
run present, complete and equal to the same run made by hand; the killed worker's `nmdp simulate`
died with it (no orphan writing on); no temporary file is left.

The workers run without nmdp's Python package on their path: the client ships the task's code."""
import csv
import json
import os
import signal
import subprocess
import sys
import time

import h5py
import pytest

from conftest import NMDP_BINARY, scene_path
from nmdp.sweep import spec

SCENE = scene_path("quadruped_trot_sand.json")
# 8 runs of about 1-2 s each on the 2-core machine (dt 5 ms for 2 s: 400 steps of the sand trot).
SWEEP = {"scene": SCENE, "base": {"duration": 2.0, "integrator.dt": 0.005},
         "grid": {"controller.gait.period": [0.4, 0.45, 0.5, 0.55], "controller.gait.stride_length": [0.1, 0.15]}}


def running_simulate(pid):
    """[(pid, command line)] of the process's children that are `nmdp simulate` (not a fork before
    its exec, which still has the worker's command line)."""
    found = []
    try:
        for tid in os.listdir(f"/proc/{pid}/task"):
            with open(f"/proc/{pid}/task/{tid}/children") as f:
                for child in f.read().split():
                    with open(f"/proc/{child}/cmdline") as c:
                        cmdline = c.read().split("\0")
                    if cmdline[1:2] == ["simulate"]:
                        found.append((int(child), cmdline))
    except OSError:
        pass
    return found


def alive(pid):
    """Whether the process exists and is not a zombie."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def wait_for(condition, timeout, what):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        value = condition()
        if value:
            return value
        time.sleep(0.02)
    pytest.fail(f"timed out waiting for {what}")


@pytest.fixture
def cluster(tmp_path):
    """(scheduler address, [worker Popen]): a scheduler on a free port and two single-threaded
    workers without a nanny (so that killing the worker's pid kills the worker), torn down after."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    address_file = tmp_path / "scheduler.json"
    logs = open(tmp_path / "cluster.log", "w")
    procs = [subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1", "--port", "0",
                               "--dashboard-address", ":0", "--scheduler-file", str(address_file)],
                              env=env, stdout=logs, stderr=subprocess.STDOUT, cwd=tmp_path)]
    try:
        wait_for(address_file.exists, 30, "the scheduler")
        address = wait_for(lambda: json.loads(address_file.read_text() or "{}").get("address"), 30, "its address")
        workers = [subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker", address, "--nthreads", "1",
                                     "--no-nanny", "--no-dashboard", "--local-directory", str(tmp_path / f"w{i}")],
                                    env=env, stdout=logs, stderr=subprocess.STDOUT, cwd=tmp_path) for i in range(2)]
        procs += workers
        from distributed import Client
        with Client(address, timeout=30) as c:
            c.wait_for_workers(2, timeout=30)
        yield address, workers
    finally:
        for p in reversed(procs):
            p.terminate()
        for p in reversed(procs):
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()
        logs.close()


def test_a_worker_killed_mid_run_has_its_run_made_elsewhere_and_the_sweep_completes(tmp_path, cluster):
    address, workers = cluster
    path = tmp_path / "sweep.json"
    path.write_text(json.dumps(SWEEP))
    out = tmp_path / "out"
    sweep = subprocess.Popen([NMDP_BINARY, "sweep", str(path), "--scheduler", address, "--out", str(out)],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        victim = workers[0]
        child, cmdline = wait_for(lambda: running_simulate(victim.pid), 60, "the worker to start a run")[0]
        victim.send_signal(signal.SIGKILL)
        victim.wait()
        wait_for(lambda: not alive(child), 0.5, "the killed worker's nmdp simulate to die with it")
        stdout, stderr = sweep.communicate(timeout=120)
    finally:
        if sweep.poll() is None:
            sweep.kill()
    assert sweep.returncode == 0, stderr
    s = spec.load(str(path))
    killed_run = os.path.basename(cmdline[cmdline.index("--out") + 1]).split(".h5.part-")[0]
    assert killed_run in [r.id for r in s.runs], cmdline
    assert sorted(os.listdir(out / "runs")) == sorted(r.id + ".h5" for r in s.runs)  # no temporary file left
    with open(out / "index.csv", newline="") as f:
        assert [row["status"] for row in csv.DictReader(f)] == ["complete"] * len(s.runs)
    for run in s.runs:
        by_hand = tmp_path / "by_hand.h5"
        sets = [a for k, v in run.overrides.items() for a in ("--set", f"{k}={v}")]
        subprocess.run([NMDP_BINARY, "simulate", SCENE, *sets, "--out", str(by_hand), "--quiet"], check=True, timeout=60)
        with h5py.File(by_hand, "r") as a, h5py.File(out / "runs" / f"{run.id}.h5", "r") as b:
            assert b["status"][()].rstrip(b"\0") == b"complete"
            assert int(b["rows"][()]) == 401 and int(b["steps"][()]) == 400
            assert a["q"][()].tobytes() == b["q"][()].tobytes(), run.overrides
