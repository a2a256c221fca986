"""A lone foot dragged sideways through the 3-D sand model (data/granular/rft3d_quadruped_rbf.h5)
meets, in simulation, the resistance that 3-D RFT predicts for that motion.

The foot is the quadruped's 0.02 m sphere on two prismatic joints (y, then z) of a fixed frame, held
about 2 cm deep by a stiff PD and pulled 0.2 m along its lateral axis (+y) by keyframes. While it
slides, the contact's force (sim.contacts, world frame) is compared with `nmdp gen-rft` in 3-D for
the same foot, medium and depth moving along +y: the drag must be within 10 % of RFT's."""
import json
import os
import subprocess

import h5py
import numpy as np

import nmdp
from conftest import NMDP_BINARY, SOURCE_DIR

URDF = """<?xml version="1.0"?>
<robot name="dragged_foot">
  <link name="frame"/>
  <link name="carriage">
    <inertial><origin xyz="0 0 0"/><mass value="0.5"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>
  </link>
  <link name="foot">
    <inertial><origin xyz="0 0 0"/><mass value="0.5"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>
  </link>
  <joint name="slide_y" type="prismatic">
    <parent link="frame"/><child link="carriage"/><origin xyz="0 0 0.1"/><axis xyz="0 1 0"/>
    <limit lower="-5" upper="5" effort="10000" velocity="10"/>
  </joint>
  <joint name="slide_z" type="prismatic">
    <parent link="carriage"/><child link="foot"/><origin xyz="0 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="10000" velocity="10"/>
  </joint>
</robot>
"""
MODEL = os.path.join(SOURCE_DIR, "data", "granular", "rft3d_quadruped_rbf.h5")
SAMPLES = os.path.join(SOURCE_DIR, "data", "granular", "rft3d_quadruped_samples.json")


def drag_run(folder):
    """Per step while the foot slides: time, foot depth (m), y velocity of the sphere (m/s), force (N)."""
    with open(os.path.join(folder, "foot.urdf"), "w") as f:
        f.write(URDF)
    # The sphere's centre is 0.1 m up at slide_z = 0: -0.1 puts it on the surface's level, so its lowest
    # point is 2 cm deep. From 0.3 s to 1.3 s the keyframes move it 0.2 m along +y.
    with open(os.path.join(folder, "drag.json"), "w") as f:
        json.dump({"times": [0, 0.3, 1.3], "joints": {"slide_y": [0, 0, 0.2], "slide_z": [-0.1, -0.1, -0.1]}}, f)
    scene = {"robot": {"urdf": "foot.urdf", "base": "fixed", "initial": {"joints": {"slide_z": -0.1}}},
             "contacts": {"points": [{"link": "foot", "radius": 0.02, "leg_axis": [0, 0, 1]}],
                          "model": {"type": "rbf", "file": MODEL}},
             "integrator": {"method": "ne-pgm", "dt": 0.01},
             "controller": {"kp": 20000, "kd": 400, "gait": {"type": "keyframes", "file": "drag.json"}},
             "duration": 1.3}
    path = os.path.join(folder, "scene.json")
    with open(path, "w") as f:
        json.dump(scene, f)
    sim = nmdp.Simulation(nmdp.Scene.load(path))
    rows, y_before = [], sim.contacts[0]["point"][1]
    for _ in range(130):
        sim.step(1)
        c = sim.contacts[0]
        rows.append((sim.time, c["depth"], (c["point"][1] - y_before) / sim.dt, *c["wrench"][3:]))
        y_before = c["point"][1]
    return np.array(rows)


def rft_force_along_y(folder, depth):
    """3-D RFT's force (N) on the shipped model's foot and medium at `depth` moving along +y."""
    with open(SAMPLES) as f:
        config = json.load(f)
    config["grid"] = {"depths": [-depth], "betas": [0], "gammas": [0], "directions": {"type": "list", "vectors": [[0, 1, 0]]}}
    out = os.path.join(folder, "rft.h5")
    subprocess.run([NMDP_BINARY, "gen-rft", "--config", json.dumps(config), "--out", out], check=True, capture_output=True)
    with h5py.File(out, "r") as f:
        names = [n.strip() for n in f["wrench"].attrs["names"].split(",")]
        w = f["wrench"][0]
    return np.array([w[names.index(k)] for k in ("F_x", "F_y", "F_z")])


def test_a_foot_dragged_sideways_meets_the_resistance_of_3d_rft(tmp_path):
    rows = drag_run(str(tmp_path))
    sliding = rows[(rows[:, 0] > 0.5) & (rows[:, 0] < 1.2)]
    assert np.all(sliding[:, 2] > 0.05), "the foot must be sliding along +y"
    depth = float(np.mean(sliding[:, 1]))
    assert 0.015 < depth < 0.025, depth
    drag = float(np.mean(sliding[:, 4]))  # world y = the foot's lateral axis
    rft = rft_force_along_y(str(tmp_path), depth)
    assert rft[1] < 0, rft
    print(f"depth {depth * 100:.2f} cm: simulated drag {drag:.3f} N, 3-D RFT {rft[1]:.3f} N")
    assert drag < 0, "the drag must oppose the motion"
    assert abs(drag - rft[1]) <= 0.10 * abs(rft[1]), (drag, rft)
    # Dragged sideways, the symmetric foot gets no force along its heading (x).
    assert np.max(np.abs(sliding[:, 3])) <= 1e-3 * abs(rft[1])
