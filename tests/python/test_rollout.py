"""nmdp.rollout: a batch of runs in C++ threads equals a loop of Simulation.step, with any number of
threads; controls drive each entry; bad input is ValueError naming the argument."""
import numpy as np
import pytest

import nmdp
from conftest import scene_path

SCENE = scene_path("quadruped_trot_flat.json")
STEPS = 12


def starts(sim, batch):
    """Distinct flat states: the scene's start, then each stepped a little further."""
    rows = []
    for b in range(batch):
        if b:
            sim.step()
        rows.append(sim.get_state())
    return np.array(rows)


def loop_of_steps(scene, x0, steps, controls=None):
    """What rollout promises, one entry at a time from Python."""
    sim = nmdp.Simulation(scene)
    out = np.empty((len(x0), steps + 1, x0.shape[1]))
    for b, x in enumerate(x0):
        sim.set_state(x)
        out[b, 0] = sim.get_state()
        for k in range(steps):
            if controls is not None:
                n = sim.nq
                sim.set_targets(controls[b, k, :n], controls[b, k, n:2 * n])
                if controls.shape[2] == 3 * n:
                    sim.set_feedforward(controls[b, k, 2 * n:])
            assert sim.step().converged
            out[b, k + 1] = sim.get_state()
    return out


@pytest.fixture(scope="module")
def scene():
    return nmdp.Scene.load(SCENE)


def test_rollout_equals_a_loop_of_step(scene):
    x0 = starts(nmdp.Simulation(scene), 3)
    states = nmdp.rollout(scene, x0, STEPS)
    assert states.shape == (3, STEPS + 1, x0.shape[1]) and states.dtype == np.float64
    assert np.array_equal(states, loop_of_steps(scene, x0, STEPS))


def test_two_threads_give_the_bits_of_one(scene):
    x0 = starts(nmdp.Simulation(scene), 5)
    one = nmdp.rollout(scene, x0, STEPS, threads=1)
    two = nmdp.rollout(scene, x0, STEPS, threads=2)
    assert np.array_equal(one, two)


def test_q_and_qdot_rows_start_as_the_scene_does(scene):
    sim = nmdp.Simulation(scene)
    qqd = np.concatenate([sim.q, sim.qdot])[None, :]
    states = nmdp.rollout(scene, qqd, STEPS)
    sim.step(STEPS)
    assert np.array_equal(states[0, -1], sim.get_state())


def test_controls_hold_targets_and_torques_per_step(scene):
    sim = nmdp.Simulation(scene)
    n = sim.nq
    x0 = starts(sim, 2)
    controls = np.zeros((2, STEPS, 3 * n))
    controls[:, :, :n] = x0[0, 1:1 + n]  # hold the start pose
    knee = sim.joint_names.index("FL_knee_joint")
    controls[1, :, knee] += np.linspace(0.0, 0.3, STEPS)
    controls[1, :, 2 * n + knee] = 0.5
    states = nmdp.rollout(scene, x0, STEPS, controls=controls)
    assert np.array_equal(states, loop_of_steps(scene, x0, STEPS, controls))
    targets_only = nmdp.rollout(scene, x0, STEPS, controls=controls[:, :, :2 * n])
    assert np.array_equal(targets_only[0], states[0])  # entry 0 has no torque
    assert not np.array_equal(targets_only[1], states[1])


def test_status_per_entry():
    failing = nmdp.Scene.load(SCENE, {"integrator.max_outer_iterations": 8, "integrator.adaptive": False})
    sim = nmdp.Simulation(failing)
    x0 = np.array([sim.get_state()] * 2)
    x0[1, 0] = 0.0
    states, status, done = nmdp.rollout(failing, x0, 12, return_status=True)
    # From the start this scene's step 10 fails (test_simulation's CLI run shows the same).
    assert status == ["outer-iteration limit reached"] * 2
    assert list(done) == [9, 9]
    assert not np.isnan(states[:, :10]).any() and np.isnan(states[:, 10:]).all()
    ok_states, ok_status, ok_done = nmdp.rollout(nmdp.Scene.load(SCENE), x0, 3, return_status=True)
    assert ok_status == ["converged"] * 2 and list(ok_done) == [3, 3]


def test_bad_input_names_the_argument(scene):
    sim = nmdp.Simulation(scene)
    x = sim.get_state()
    with pytest.raises(ValueError, match=r"^initial_states: expected an array of shape \(B, nx\)"):
        nmdp.rollout(scene, x, 3)
    with pytest.raises(ValueError, match="initial_states"):
        nmdp.rollout(scene, np.zeros((2, 5)), 3)
    bad = np.array([x, x])
    bad[1, 2] = np.nan
    with pytest.raises(ValueError, match="initial_states"):
        nmdp.rollout(scene, bad, 3)
    n = sim.nq
    with pytest.raises(ValueError, match=rf"^controls: expected an array of shape \(1, 3, {2 * n}\) \(B, steps, 2 nq: q and qdot "
                                         rf"targets per step\) or \(1, 3, {3 * n}\) \(and the feed-forward torque\); got shape \(1, 2, {2 * n}\)$"):
        nmdp.rollout(scene, x[None, :], 3, controls=np.zeros((1, 2, 2 * sim.nq)))
    fresh = nmdp.Scene.load(SCENE)  # no Simulation built from it yet: the check loads the robot for nq
    with pytest.raises(ValueError, match=rf"^controls: expected an array of shape \(1, 3, {2 * n}\) .* got shape \(1, 3, 5\)$"):
        nmdp.rollout(fresh, x[None, :], 3, controls=np.zeros((1, 3, 5)))
    with pytest.raises(ValueError, match="steps"):
        nmdp.rollout(scene, x[None, :], 0)
    with pytest.raises(ValueError, match="threads"):
        nmdp.rollout(scene, x[None, :], 3, threads=0)


def test_rollout_lets_other_python_threads_run(scene):
    import threading
    import time
    x0 = starts(nmdp.Simulation(scene), 1).repeat(40, axis=0)
    result = {}
    worker = threading.Thread(target=lambda: result.setdefault("states", nmdp.rollout(scene, x0, 20)))
    start = time.perf_counter()
    worker.start()
    ticks = [start]
    while worker.is_alive():
        time.sleep(0.001)
        ticks.append(time.perf_counter())
    worker.join()
    took = ticks[-1] - start
    # Holding the GIL, the rollout would stop this loop for its whole length; released, it ticks on.
    assert took > 0.2 and max(np.diff(ticks)) < took / 3, (took, max(np.diff(ticks)))
    assert result["states"].shape == (40, 21, x0.shape[1])
