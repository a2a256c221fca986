"""sim.get_state() / sim.set_state(x): the flat state restores a run bit for bit; and
sim.set_feedforward(tau) drives a joint as the PD law says."""
import numpy as np
import pytest

import nmdp
from conftest import record, scene_path

RUNS = [("quadruped_trot_sand.json", {}), ("quadruped_trot_flat.json", {})]
IDS = ["sand trot", "floating-base trot"]


@pytest.mark.parametrize("scene,overrides", RUNS, ids=IDS)
def test_a_restored_state_repeats_the_run_bit_for_bit(scene, overrides):
    loaded = nmdp.Scene.load(scene_path(scene), overrides)
    sim = nmdp.Simulation(loaded)
    sim.step(7)  # mid-stride: contacts, warm starts and (floating base) a rebased chart in the state
    x = sim.get_state()
    original = record(sim, 15)
    sim.step(3)
    sim.set_state(x)
    assert np.array_equal(sim.get_state(), x)
    assert np.array_equal(record(sim, 15)["q"], original["q"])
    other = nmdp.Simulation(loaded)  # another simulation of the same scene, never stepped
    other.set_state(x)
    repeated = record(other, 15)
    for key in ("time", "q", "qdot"):
        assert np.array_equal(repeated[key], original[key]), key


def test_the_flat_state_starts_with_time_q_and_qdot():
    sim = nmdp.Simulation(nmdp.Scene.load(scene_path("quadruped_trot_flat.json")))
    sim.step(3)
    x, layout = sim.get_state(), sim.state_layout
    assert list(layout)[:3] == ["time", "q", "qdot"]
    assert x[0] == sim.time and x[layout["time"]][0] == sim.time
    assert np.array_equal(x[layout["q"]], sim.q) and np.array_equal(x[1:1 + sim.nq], sim.q)
    assert np.array_equal(x[layout["qdot"]], sim.qdot)
    assert sum(s.stop - s.start for s in layout.values()) == len(x)
    x[1] = 99.0
    assert sim.q[0] != 99.0  # get_state is a copy


def test_views_show_the_restored_state():
    sim = nmdp.Simulation(nmdp.Scene.load(scene_path("quadruped_trot_flat.json")))
    q = sim.q
    start = sim.get_state()
    sim.step(5)
    sim.set_state(start)
    assert np.array_equal(q, start[sim.state_layout["q"]])
    assert sim.stats is None and all(not c["wrench"].any() for c in sim.contacts)


def test_bad_states_are_value_errors_naming_the_part():
    sim = nmdp.Simulation(nmdp.Scene.load(scene_path("quadruped_trot_flat.json")))
    x = sim.get_state()
    with pytest.raises(ValueError, match=rf"^state: expected {len(x)} entries, got 3$"):
        sim.set_state(x[:3])
    bad = x.copy()
    bad[sim.state_layout["qdot"].start + 2] = np.nan
    with pytest.raises(ValueError, match="qdot"):
        sim.set_state(bad)
    assert np.array_equal(sim.get_state(), x)  # a refused state changes nothing


def hanging_robot():
    """The quadruped bolted to the world with its legs in the air (the ground a metre below)."""
    return nmdp.Simulation(nmdp.Scene.load(scene_path("quadruped_stand_flat.json"),
                                           {"robot.base": "fixed", "terrain.offset": -1.0}))


def test_a_feedforward_torque_deflects_the_joint_by_tau_over_kp():
    held, pushed = hanging_robot(), hanging_robot()
    knee = pushed.joint_names.index("FL_knee_joint")
    kp = pushed.config["controller"]["kp"]["FL_knee_joint"]
    tau = np.zeros(pushed.nq)
    tau[knee] = 0.5  # N·m: 0.03 rad at kp ≈ 16 N·m/rad
    pushed.set_feedforward(tau)
    held.step(40)
    pushed.step(40)  # 2 s: settled
    deflection = pushed.q[knee] - held.q[knee]
    assert deflection == pytest.approx(tau[knee] / kp, rel=0.1)
    others = np.arange(pushed.nq) != knee
    assert np.max(np.abs(pushed.q[others] - held.q[others])) < 0.1 * deflection


def test_feedforward_errors():
    sim = nmdp.Simulation(nmdp.Scene.load(scene_path("quadruped_trot_flat.json")))
    with pytest.raises(ValueError, match=rf"^tau: expected {sim.nq} entries, got 2$"):
        sim.set_feedforward([1.0, 2.0])
    tau = np.zeros(sim.nq)
    tau[sim.joint_names.index("FR_knee_joint")] = np.inf
    with pytest.raises(ValueError, match="FR_knee_joint|entry"):
        sim.set_feedforward(tau)
    tau[:] = 0.0
    tau[0] = 1.0  # base_x: unactuated
    with pytest.raises(ValueError):
        sim.set_feedforward(tau)
