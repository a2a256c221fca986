"""The package as docs/PYTHON.md says: a folder that works wherever it is copied (no pip), and
sim.step() releases the GIL so that other Python threads run while it steps (but do not step it)."""
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


def test_step_releases_the_gil_but_one_thread_at_a_time_steps():
    sim = nmdp.Simulation(nmdp.Scene.load(scene_path("quadruped_trot_flat.json"), {"duration": 100}))
    stepping = threading.Thread(target=sim.step, args=(400,))
    stepping.start()
    try:
        # This thread runs Python while the other steps: it sees the time move during step(400).
        # (Holding the GIL, step would let it read only the final time.)
        seen = set()
        while len(seen) < 3 and stepping.is_alive():
            seen.add(sim.time)
            time.sleep(0.001)
        assert stepping.is_alive() and len(seen) == 3, "the time did not move while the other thread stepped"
        with pytest.raises(RuntimeError, match="being stepped by another thread"):
            sim.step()
        with pytest.raises(RuntimeError, match="being stepped by another thread"):
            sim.set_targets(sim.q.copy())
    finally:
        stepping.join()
    assert sim.step().converged  # free again


def test_ctrl_c_interrupts_a_long_step_call_between_steps(tmp_path):
    program = f"""
import os, signal, threading, nmdp
sim = nmdp.Simulation(nmdp.Scene.load({scene_path('quadruped_foot_drop_sand.json')!r}, {{"duration": 1e6}}))
threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGINT)).start()
try:
    sim.step(10**9)
    print("not interrupted")
except KeyboardInterrupt:
    steps = sim.time / sim.dt
    print("interrupted", steps, abs(steps - round(steps)) < 1e-6, sim.step().converged)
"""
    done = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    word, steps, whole, stepped_on = done.stdout.split()
    assert word == "interrupted" and float(steps) > 100 and whole == "True" and stepped_on == "True", done.stdout
