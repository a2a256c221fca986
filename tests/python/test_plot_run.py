"""scripts/plot_run.py on a run of `nmdp simulate`: the step count it reports is the time steps of dt
the run took (/steps), not its rows (which include t = 0), also with output.every > 1."""
import os
import re
import subprocess

import pytest

from conftest import SOURCE_DIR, run_cli, scene_path

PLOT_RUN = os.path.join(SOURCE_DIR, "scripts", "plot_run.py")


def plot(run, png):
    """plot_run.py with Debian's python3 (its h5py and matplotlib): the summary line."""
    if subprocess.run(["/usr/bin/python3", "-c", "import h5py, matplotlib"], capture_output=True).returncode != 0:
        pytest.skip("/usr/bin/python3 lacks h5py or matplotlib (scripts/install-deps.sh)")
    done = subprocess.run(["/usr/bin/python3", PLOT_RUN, str(run), str(png)], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    return done.stdout


@pytest.mark.parametrize("every, rows", [(1, 21), (3, 8)])
def test_plot_run_reports_the_time_steps(tmp_path, every, rows):
    out = tmp_path / "run.h5"
    done = run_cli(scene_path("quadruped_stand_flat.json"), {"duration": 1.0, "integrator.dt": 0.05, "output.every": every}, out)
    assert done.returncode == 0, done.stderr
    line = plot(out, tmp_path / "run.png")
    # 20 steps of 50 ms; rows: t = 0, every `every`-th step and the last one.
    assert re.search(r": 20 steps \(%d rows\)" % rows, line), line
