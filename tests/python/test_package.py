"""The package as docs/PYTHON.md says: a folder that works wherever it is copied (no pip), and
sim.step() releases the GIL so that other Python threads run while it steps."""
import os
import shutil
import subprocess
import sys
import threading
import time

import pytest

import nmdp
from conftest import scene_path


def test_the_package_folder_works_when_copied_elsewhere(tmp_path):
    site = tmp_path / "site"
    shutil.copytree(os.path.dirname(nmdp.__file__), site / "nmdp")
    program = ("import nmdp, sys; "
               f"sim = nmdp.Simulation(nmdp.Scene.load({scene_path('quadruped_stand_flat.json')!r})); "
               "sim.step(2); print(nmdp.__file__, sim.time)")
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["PYTHONPATH"] = str(site)
    done = subprocess.run([sys.executable, "-c", program], cwd=tmp_path, env=env, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    where, t = done.stdout.split()
    assert where.startswith(str(site)) and float(t) == pytest.approx(0.1)


def test_step_lets_other_python_threads_run():
    sim = nmdp.Simulation(nmdp.Scene.load(scene_path("quadruped_trot_flat.json")))
    count, stop = [0], threading.Event()

    def count_while_stepping():
        while not stop.is_set():
            count[0] += 1

    sim.step()  # warmed up
    counter = threading.Thread(target=count_while_stepping)
    counter.start()
    try:
        time.sleep(0.01)
        before = count[0]
        start = time.perf_counter()
        sim.step(100)
        stepped = time.perf_counter() - start
        during = count[0] - before
    finally:
        stop.set()
        counter.join()
    # Holding the GIL, the step would leave the counter no turn at all; released, it counts all along.
    assert stepped > 0.02 and during > 1000, (stepped, during)


def test_a_second_thread_cannot_step_the_same_simulation_meanwhile():
    sim = nmdp.Simulation(nmdp.Scene.load(scene_path("quadruped_trot_flat.json"), {"duration": 100}))
    stepping = threading.Thread(target=sim.step, args=(400,))
    stepping.start()
    try:
        while sim.time == 0.0 and stepping.is_alive():
            time.sleep(0.001)
        assert stepping.is_alive(), "the first thread finished too soon to test anything"
        with pytest.raises(RuntimeError, match="being stepped by another thread"):
            sim.step()
        with pytest.raises(RuntimeError, match="being stepped by another thread"):
            sim.set_targets(sim.q.copy())
    finally:
        stepping.join()
    assert sim.step().converged  # free again
