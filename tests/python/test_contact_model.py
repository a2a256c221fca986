"""nmdp.ContactModel: built by the registry from a scene's contacts.model object; its vertices equal
what `nmdp wrench` prints for the same foot (a separate process through the CLI), match the models'
own definitions (the Coulomb cone's formula, the RBF's interpolated data at the measured points with
the torque moved to the sphere centre), are continuous in depth with dV/dxi matching finite
differences, and zero above the cut-off; wrench_space gives a hull that encloses every projected
vertex; bad input is a ValueError with the CLI's message."""
import json
import os
import subprocess

import numpy as np
import pytest

import nmdp
from conftest import NMDP_BINARY, SOURCE_DIR, shared_or_skip

RFT_MODEL = os.path.join(SOURCE_DIR, "data", "granular", "rft_quadruped_rbf.h5")
RFT_SAMPLES = os.path.join(SOURCE_DIR, "data", "granular", "rft_quadruped_samples")
ROWS_FX, ROWS_FY, ROWS_FZ, ROW_TY = 3, 4, 5, 1


def wrench_cli(config, depth, angle, radius=0.02, derivatives=False):
    """(V, dV or None) as `nmdp wrench` prints them (JSON columns of 6 → 6 × K)."""
    args = [NMDP_BINARY, "wrench", "--model", json.dumps(config), "--depth", repr(depth), "--angle", repr(angle),
            "--radius", repr(radius)] + (["--derivatives"] if derivatives else [])
    out = json.loads(subprocess.run(args, check=True, capture_output=True, text=True).stdout)
    V = np.array(out["V"]).T
    dV = np.array([np.array(d).T for d in out["dV"]]) if derivatives else None
    return V, dV


def cli_error(args):
    """The message `nmdp ...` prints on stderr for bad input, without its "nmdp X: error: " prefix."""
    run = subprocess.run([NMDP_BINARY] + args, capture_output=True, text=True)
    assert run.returncode == 1, run.stderr
    return run.stderr.strip().split(": error: ", 1)[1]


def test_coulomb_properties_and_formula():
    model = nmdp.ContactModel.from_config({"type": "coulomb", "mu": 0.8})
    assert model.vertex_count == 6 and model.derivative == "analytic"
    assert model.describe().startswith("coulomb: mu 0.8")
    config = model.configuration()
    assert config["type"] == "coulomb" and config["mu"] == 0.8 and config["K"] == 6
    # V_i = k (d^p + zeta) (n + mu (cos phi_i t1 + sin phi_i t2)), d = -depth, torque (-r n) x F.
    k, p, zeta, r = config["k"], config["p"], config["zeta"], 0.02
    V = model.vertices(-0.01, 0.3, radius=r)
    normal = k * (0.01 ** p + zeta)
    angles = 2 * np.pi * np.arange(6) / 6
    np.testing.assert_allclose(V[ROWS_FZ], normal, rtol=1e-12)
    np.testing.assert_allclose(V[ROWS_FX], 0.8 * normal * np.cos(angles), rtol=1e-12, atol=1e-9 * normal)
    np.testing.assert_allclose(V[ROWS_FY], 0.8 * normal * np.sin(angles), rtol=1e-12, atol=1e-9 * normal)
    np.testing.assert_allclose(V[0:3], np.stack([r * V[ROWS_FY], -r * V[ROWS_FX], 0 * V[ROWS_FX]]), atol=1e-12)
    # Above the surface the cone keeps its documented force in the air, k zeta (0.1 N).
    np.testing.assert_allclose(model.vertices(0.01, 0.0)[ROWS_FZ], k * zeta, rtol=1e-12)
    # The configuration rebuilds the same model.
    again = nmdp.ContactModel.from_config(config)
    assert np.array_equal(again.vertices(-0.01, 0.3), V)


@pytest.mark.parametrize("depth,angle", [(-0.02, 0.0), (-0.013, 0.41), (-0.031, -0.9), (0.004, 0.2)])
def test_rbf_vertices_equal_nmdp_wrench(depth, angle):
    config = {"type": "rbf", "file": RFT_MODEL}
    model = nmdp.ContactModel.from_config(config)
    V, dV = model.vertices(depth, angle, with_derivatives=True)
    cli_V, cli_dV = wrench_cli(config, depth, angle, derivatives=True)
    assert np.array_equal(V, cli_V)
    assert np.array_equal(dV, cli_dV)


def test_coulomb_vertices_equal_nmdp_wrench():
    config = {"type": "coulomb", "mu": 0.6, "K": 8}
    V = nmdp.ContactModel.from_config(config).vertices(-0.004, 0.3, radius=0.03)
    assert np.array_equal(V, wrench_cli(config, -0.004, 0.3, radius=0.03)[0])


def test_rbf_reproduces_its_data_at_the_measured_points():
    """The fitted RBF interpolates the samples: at every measured point below the cut-off band the
    forces are the data's (F_x, F_z) in the x-z plane, and the torque about the sphere centre is the
    data's tau_y (about the torque centre Q, L up the leg) moved: tau_y + (L cos b - r) F_x - L sin b F_z.
    This pins the features: depth = phi, angle = beta."""
    model = nmdp.ContactModel.from_config({"type": "rbf", "file": RFT_MODEL})
    L, r = model.configuration()["torque_centre"], 0.02
    samples = np.genfromtxt(os.path.join(RFT_SAMPLES, "wrench_samples.csv"), delimiter=",", names=True)
    below = samples[samples["depth"] <= -0.005]
    assert len(below) > 100
    scale = np.abs(below["fz"]).max()
    for depth in np.unique(below["depth"]):
        for angle in np.unique(below["theta"][below["depth"] == depth]):
            rows = below[(below["depth"] == depth) & (below["theta"] == angle)]
            V = model.vertices(depth, angle, radius=r)[:, rows["vel_index"].astype(int)]
            np.testing.assert_allclose(V[ROWS_FX], rows["fx"], atol=1e-8 * scale)
            np.testing.assert_allclose(V[ROWS_FZ], rows["fz"], atol=1e-8 * scale)
            assert np.all(V[ROWS_FY] == 0)
            torque = rows["wy"] + (L * np.cos(angle) - r) * rows["fx"] - L * np.sin(angle) * rows["fz"]
            np.testing.assert_allclose(V[ROW_TY], torque, atol=1e-9 * scale)
    # This data is mirror symmetric, so the sign of the angle shows only in the lever arm: moving the
    # torque centre by dL up the leg a = (sin b, 0, cos b) changes the torque about the sphere centre
    # by dL (cos b F_x - sin b F_z).
    moved = nmdp.ContactModel.from_config({"type": "rbf", "file": RFT_MODEL, "torque_centre": L + 0.1})
    for angle in (0.5, -0.8):
        V, W = model.vertices(-0.02, angle), moved.vertices(-0.02, angle)
        lever = 0.1 * (np.cos(angle) * V[ROWS_FX] - np.sin(angle) * V[ROWS_FZ])
        np.testing.assert_allclose(W[ROW_TY] - V[ROW_TY], lever, atol=1e-12 * scale)


def test_vertices_continuous_in_depth_derivative_matches_and_zero_above_cutoff():
    model = nmdp.ContactModel.from_config({"type": "rbf", "file": RFT_MODEL})
    depths = np.linspace(-0.06, 0.01, 701)
    V = model.vertices(depths, 0.35)
    assert V.shape == (701, 6, 13)
    scale = np.abs(V).max()
    assert np.abs(np.diff(V, axis=0)).max() < 0.02 * scale  # 0.1 mm steps: no jump
    assert np.all(V[depths >= 0.0] == 0)  # the cut-off is at the surface (0 m)
    # Moving the sphere up by h (xi_5 = translation along z) raises the depth by h.
    h = 1e-6
    for depth in (-0.03, -0.012, -0.002):
        _, dV = model.vertices(depth, 0.35, with_derivatives=True)
        numeric = (model.vertices(depth + h, 0.35) - model.vertices(depth - h, 0.35)) / (2 * h)
        np.testing.assert_allclose(dV[5], numeric, atol=1e-5 * np.abs(numeric).max())


def test_arrays_broadcast_and_equal_single_calls():
    model = nmdp.ContactModel.from_config({"type": "rbf", "file": RFT_MODEL})
    depths = np.array([[-0.01], [-0.02]])
    angles = np.array([0.0, 0.3, -0.5])
    V, dV = model.vertices(depths, angles, with_derivatives=True)
    assert V.shape == (2, 3, 6, 13) and dV.shape == (2, 3, 6, 6, 13)
    for i in range(2):
        for j in range(3):
            single, single_d = model.vertices(depths[i, 0], angles[j], with_derivatives=True)
            np.testing.assert_allclose(V[i, j], single, rtol=1e-13, atol=1e-13 * np.abs(single).max())
            np.testing.assert_allclose(dV[i, j], single_d, rtol=1e-12, atol=1e-12 * np.abs(single_d).max())


def signed_area(hull):
    x, y = hull[:, 0], hull[:, 1]
    return 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)


def test_wrench_space_hull_encloses_every_vertex():
    model = nmdp.ContactModel.from_config({"type": "rbf", "file": RFT_MODEL})
    ws = model.wrench_space(-0.02, 0.4)
    assert ws["axes"] == ("fx", "fz")
    V = model.vertices(-0.02, 0.4)
    assert np.array_equal(ws["vertices"], V)
    assert np.array_equal(ws["points"], V[[ROWS_FX, ROWS_FZ]].T)
    hull = ws["hull"]
    assert np.array_equal(hull, ws["points"][ws["hull_indices"]])
    assert len(hull) >= 3 and signed_area(hull) > 0  # counter-clockwise
    scale = np.abs(hull).max()
    for a, b in zip(hull, np.roll(hull, -1, axis=0)):  # every point on the left of every edge
        edge, rel = b - a, ws["points"] - a
        assert np.all(edge[0] * rel[:, 1] - edge[1] * rel[:, 0] >= -1e-9 * scale ** 2)
    # Other axes, and the degenerate cases: collinear (the Coulomb cone's forces on flat ground have
    # one normal force) and a single point (nothing above the surface).
    assert model.wrench_space(-0.02, 0.4, axes=("fx", "ty"))["hull"].shape[1] == 2
    cone = nmdp.ContactModel.from_config({"type": "coulomb"}).wrench_space(-0.01, 0.0)
    assert cone["hull"].shape == (2, 2)
    assert model.wrench_space(0.01, 0.0)["hull"].shape == (1, 2)


def test_published_robosimian_model_equals_nmdp_wrench():
    folder = shared_or_skip("granular", "robosimian_sand_rbf")
    config = {"type": "rbf", "file": "robosimian_sand_rbf"}
    model = nmdp.ContactModel.from_config(config, base_dir=os.path.dirname(folder))
    assert model.configuration()["format"] == "published" and model.vertex_count == 26
    V = model.vertices(-0.03, 0.2)
    assert np.array_equal(V, wrench_cli({"type": "rbf", "file": folder}, -0.03, 0.2)[0])
    assert np.abs(V).max() > 1.0


def test_mlp_model_from_a_short_fit_equals_nmdp_wrench(tmp_path):
    out = str(tmp_path / "mlp.h5")
    nmdp.fit(RFT_SAMPLES, "mlp", {"mlp": {"max_epochs": 3, "width": 8}}, out=out)
    config = {"type": "mlp", "file": out}
    model = nmdp.ContactModel.from_config(config)
    assert model.derivative == "autograd" and model.vertex_count == 13
    V, dV = model.vertices(-0.02, 0.3, with_derivatives=True)
    cli_V, cli_dV = wrench_cli(config, -0.02, 0.3, derivatives=True)
    assert np.array_equal(V, cli_V) and np.array_equal(dV, cli_dV)


def test_bad_input_is_value_error_with_the_cli_message(tmp_path):
    for config in ({"type": "coulomb", "mu": -1}, {"type": "coulom"}, {"type": "rbf", "file": str(tmp_path / "x.h5")},
                   {"type": "coulomb", "mu": 0.5, "colour": 1}):
        with pytest.raises(ValueError) as raised:
            nmdp.ContactModel.from_config(config)
        assert str(raised.value) == cli_error(["wrench", "--model", json.dumps(config)])
    with pytest.raises(ValueError, match="expected a dict"):
        nmdp.ContactModel.from_config("coulomb")
    model = nmdp.ContactModel.from_config({"type": "coulomb"})
    with pytest.raises(ValueError, match=r"depth\[1\]: nan is not a finite number"):
        model.vertices(np.array([0.0, np.nan]), 0.0)
    with pytest.raises(ValueError, match="angle: .* is beyond"):
        model.vertices(0.0, 1e6)
    with pytest.raises(ValueError, match="radius: must be >= 0"):
        model.vertices(0.0, 0.0, radius=-1)
    with pytest.raises(ValueError, match="depth: expected a number"):
        model.vertices("deep", 0.0)
    with pytest.raises(ValueError, match="axes: 'fq' is not a row of V"):
        model.wrench_space(0.0, 0.0, axes=("fx", "fq"))
