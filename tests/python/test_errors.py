"""Bad input reaches Python as ValueError carrying the message `nmdp simulate` prints for it."""
import numpy as np
import pytest

import nmdp
from conftest import cli_error, scene_path

STAND = scene_path("quadruped_stand_flat.json")


def python_error(scene, overrides):
    """The ValueError's message for loading the scene and building its simulation from Python."""
    with pytest.raises(ValueError) as raised:
        nmdp.Simulation(nmdp.Scene.load(scene, overrides))
    return str(raised.value)


@pytest.mark.parametrize("overrides", [
    {"integrator.dtt": 0.1},                  # unknown key (with its suggestion)
    {"integrator.dt": -1},                    # bad value
    {"robot.urdf": "no_such_robot.urdf"},     # missing URDF
    {"controller.kp.FL_kne": 3},              # found wrong only with the robot loaded
    {"integrator.method": "ne-zopgn"},        # a plain string that is not a method
], ids=["unknown key", "bad value", "missing URDF", "unknown joint", "unknown method"])
def test_value_error_has_the_cli_message(overrides, tmp_path):
    assert python_error(STAND, overrides) == cli_error(STAND, overrides, tmp_path / "out.h5")


def test_missing_scene_file_has_the_cli_message(tmp_path):
    missing = str(tmp_path / "no_such_scene.json")
    assert python_error(missing, {}) == cli_error(missing, {}, tmp_path / "out.h5")


def test_malformed_scene_file_has_the_cli_message(tmp_path):
    broken = tmp_path / "broken.json"
    broken.write_text('{"robot": {"urdf": "a.urdf",}}')
    assert python_error(str(broken), {}) == cli_error(str(broken), {}, tmp_path / "out.h5")


def test_shape_errors_name_the_argument_and_the_shape():
    sim = nmdp.Simulation(nmdp.Scene.load(STAND))
    with pytest.raises(ValueError, match=rf"^q_target: expected {sim.nq} entries, got 3$"):
        sim.set_targets([0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match=rf"^qdot_target: expected a vector of {sim.nq} entries, got an array of shape \(2, {sim.nq}\)$"):
        sim.set_targets(sim.q.copy(), np.zeros((2, sim.nq)))
    with pytest.raises(ValueError, match=r"^q_target: expected numbers: could not convert string to float"):
        sim.set_targets(["a"] * sim.nq)
    with pytest.raises(ValueError, match=r"^n: expected a positive number of steps, got 0$"):
        sim.step(0)


def test_a_nan_target_names_the_joint_but_base_entries_are_ignored():
    sim = nmdp.Simulation(nmdp.Scene.load(STAND))
    target = sim.q.copy()
    knee = sim.joint_names.index("FR_knee_joint")
    target[knee] = np.nan
    with pytest.raises(ValueError, match=rf"^q_target: entry {knee} \(FR_knee_joint\) is nan; expected a finite number$"):
        sim.set_targets(target)
    target[knee] = sim.q[knee]
    target[~sim.actuated] = np.nan  # base coordinates: never read
    sim.set_targets(target)
    assert sim.step().converged
