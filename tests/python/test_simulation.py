"""nmdp.Simulation: a run stepped from Python is the CLI's run bit for bit; q and qdot are read-only
views of the state that keep their owner alive; PD targets set from Python drive the robot."""
import gc

import numpy as np
import pytest

import nmdp
from conftest import read_run, record, run_cli, scene_path

# The sand trot (planar base, RBF granular model, pbd-pgm) and a floating-base trot (ne-pgm, whose
# base chart is rebased as the trunk turns), each for 2 s.
RUNS = [("quadruped_trot_sand.json", {"duration": 2}),
        ("quadruped_trot_flat.json", {"duration": 2, "integrator.method": "ne-pgm"})]


@pytest.mark.parametrize("scene,overrides", RUNS, ids=["sand trot", "floating-base trot"])
def test_a_python_run_equals_the_cli_run_bit_for_bit(scene, overrides, tmp_path):
    out = tmp_path / "run.h5"
    done = run_cli(scene_path(scene), overrides, out)
    assert done.returncode == 0, done.stderr
    cli = read_run(out)

    sim = nmdp.Simulation(nmdp.Scene.load(scene_path(scene), overrides))
    assert sim.joint_names == cli["joint_names"]
    assert [c["name"] for c in sim.contacts] == cli["contact_names"]
    rows = {"time": [sim.time], "q": [sim.q.copy()], "qdot": [sim.qdot.copy()]}
    for i in range(sim.scheduled_steps):
        stats = sim.step()
        assert stats.converged, stats
        rows["time"].append(sim.time)
        rows["q"].append(sim.q.copy())
        rows["qdot"].append(sim.qdot.copy())
        # What a step reports and the wrench it carried are the file's too.
        assert stats.outer_iterations == cli["outer_iterations"][i + 1]
        assert stats.substeps == cli["substeps"][i + 1]
        assert np.array_equal(np.array([c["wrench"] for c in sim.contacts]), cli["wrench"][i + 1])
    assert cli["status"] == "complete" and len(cli["time"]) == sim.scheduled_steps + 1
    for key in ("time", "q", "qdot"):
        assert np.array_equal(np.array(rows[key]), cli[key]), key


def test_step_n_equals_n_single_steps():
    scene = nmdp.Scene.load(scene_path("quadruped_trot_flat.json"), {"duration": 1})
    one_by_one, at_once = nmdp.Simulation(scene), nmdp.Simulation(scene)
    for _ in range(20):
        last = one_by_one.step()
    stats = at_once.step(20)
    assert at_once.time == one_by_one.time
    assert np.array_equal(at_once.q, one_by_one.q) and np.array_equal(at_once.qdot, one_by_one.qdot)
    without_clock = lambda d: {k: v for k, v in d.items() if k != "wall_time"}
    assert without_clock(stats.to_dict()) == without_clock(last.to_dict())
    assert at_once.stats.outer_iterations == stats.outer_iterations


def test_step_stops_at_a_step_that_does_not_converge(tmp_path):
    # Eight outer iterations without sub-stepping: step 10 fails (the CLI keeps 9 completed steps).
    overrides = {"duration": 2, "integrator.max_outer_iterations": 8, "integrator.adaptive": False}
    done = run_cli(scene_path("quadruped_trot_flat.json"), overrides, tmp_path / "run.h5")
    assert done.returncode == 4 and "step 10 (from t = 0.45 s) failed: outer-iteration limit reached" in done.stderr
    sim = nmdp.Simulation(nmdp.Scene.load(scene_path("quadruped_trot_flat.json"), overrides))
    stats = sim.step(40)
    assert not stats.converged and stats.status == "outer-iteration limit reached"
    assert sim.stats.status == stats.status
    again = nmdp.Simulation(nmdp.Scene.load(scene_path("quadruped_trot_flat.json"), overrides))
    rows = record(again, 40)
    cli = read_run(tmp_path / "run.h5")
    assert len(rows["time"]) == len(cli["time"]) == 10
    assert np.array_equal(rows["q"], cli["q"])


def test_q_and_qdot_view_the_state():
    sim = nmdp.Simulation(nmdp.Scene.load(scene_path("quadruped_trot_flat.json")))
    q, qdot = sim.q, sim.qdot
    before = q.copy()
    assert not q.flags.writeable and not qdot.flags.writeable and not q.flags.owndata
    with pytest.raises(ValueError):
        q[0] = 1.0
    # Step by step (steps of 5 to 16 sub-steps, odd and even counts): the views never lag.
    for _ in range(10):
        sim.step()
        assert np.array_equal(q, sim.get_state()[sim.state_layout["q"]])
        assert np.array_equal(qdot, sim.get_state()[sim.state_layout["qdot"]])
        assert q.ctypes.data == sim.q.ctypes.data and qdot.ctypes.data == sim.qdot.ctypes.data
    assert not np.array_equal(q, before)


def test_a_view_keeps_its_simulation_alive():
    sim = nmdp.Simulation(nmdp.Scene.load(scene_path("quadruped_trot_flat.json")))
    sim.step(2)
    q = sim.q
    expected = q.copy()
    assert type(q.base).__name__ == "Simulation"
    del sim
    gc.collect()
    # Memory freed by the Simulation would now be reused by these.
    others = [nmdp.Simulation(nmdp.Scene.load(scene_path("quadruped_trot_flat.json"))) for _ in range(3)]
    clutter = [np.full(len(expected), 7.0) for _ in range(1000)]
    assert np.array_equal(q, expected)
    assert others and clutter


def test_holding_the_standing_pose_keeps_the_torso_up():
    # The trot scene's gait replaced by its own start pose, held: the robot stands instead of trotting.
    scene = nmdp.Scene.load(scene_path("quadruped_trot_flat.json"))
    held, trotting = nmdp.Simulation(scene), nmdp.Simulation(scene)
    z = held.joint_names.index("base_z")
    start = held.q.copy()
    held.set_targets(start)
    for _ in range(40):  # 2 s
        assert held.step().converged
        assert abs(held.q[z] - start[z]) < 0.02
    trotting.step(40)
    joints = held.actuated
    assert np.max(np.abs(held.q[joints] - start[joints])) < 0.02
    assert np.max(np.abs(trotting.q[joints] - start[joints])) > 0.1  # what the held targets prevented


def test_a_joint_target_moves_the_joint_there():
    sim = nmdp.Simulation(nmdp.Scene.load(scene_path("quadruped_stand_flat.json")))
    knee = sim.joint_names.index("FL_knee_joint")
    target = sim.q.copy()
    target[knee] += 0.3
    sim.set_targets(target)
    sim.step(20)  # 1 s
    assert abs(sim.q[knee] - target[knee]) < 0.1, (sim.q[knee], target[knee])


def test_contacts_describe_the_feet_on_the_ground():
    sim = nmdp.Simulation(nmdp.Scene.load(scene_path("quadruped_stand_flat.json")))
    sim.step(10)
    contacts = sim.contacts
    assert len(contacts) == 4
    weight = 0.0
    for c in contacts:
        assert set(c) == {"name", "point", "radius", "depth", "normal", "wrench"}
        assert abs(c["point"][2] - (c["radius"] - c["depth"])) < 1e-12  # plane at z = 0: φ = z
        assert -0.005 < c["depth"] < 0.005                            # standing: the feet touch the ground
        weight += c["wrench"][5]
    x, rpy = sim.base_pose()
    assert x.shape == (3,) and rpy.shape == (3,)
    assert weight > 0  # the ground carries the robot
