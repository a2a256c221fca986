#!/usr/bin/python3
"""Writes data/granular/handmade_sand_rbf.h5: a small hand-made RBF granular contact model.

Usage:  scripts/make_handmade_sand_model.py [OUT.h5]     (default: data/granular/handmade_sand_rbf.h5)
Needs Debian's python3-numpy and python3-h5py (scripts/install-deps.sh), hence /usr/bin/python3.
Deterministic: no randomness, a fixed grid and one linear solve.

What the model represents
-------------------------
A soft, sand-like ground for the project's quadruped (models/quadruped/quadruped.urdf: 17.4 kg,
four spherical feet of radius r = 0.02 m), not a fit to measured data. It has the layout of the
published RoboSimian sand model (../shared/granular/robosimian_sand_rbf, read by
contact_models/rbf_function.*): features f = (phi, beta) -- phi the signed distance of the foot
point to the sand surface (m, negative below), beta the leg's angle from the terrain normal in the
sagittal plane (rad, positive when the leg leans toward x_s) -- and K = 26 vertices, each a planar
wrench (F_x, F_z, tau_y) in the sagittal frame (x_s along the ground, z along the normal).

Vertex j is the sand's reaction when the foot is pushed along the direction psi_j = 2 pi j / 26
from straight down (psi = 0) toward +x_s (psi = pi/2) and up (psi = pi). The wrench polytope is the
convex hull of these 26 wrenches and the origin, like the published model's 26 probing directions.
Mirror symmetry holds (beta -> -beta maps vertex j to vertex 26 - j with F_x, tau_y negated), as in
the published data.

Numbers (all below; sinkage d = max(0, -phi)):
  * Bearing capacity, resistive-force-theory style: stress grows linearly with depth and acts on the
    buried part of the sphere's horizontal cross-section,
        F_b(d, beta) = SIGMA_Z * d * A(d) * (1 + TILT_GAIN sin^2 beta),
        A(d) = pi (2 r d - d^2) for d <= r, pi r^2 below the equator (C^1 there).
    SIGMA_Z makes F_b(1.5 cm, 0) = 17.4 * 9.81 / 4 = 42.7 N: the robot standing on four upright feet
    sinks about 1.5 cm. Then F_b = 23 N at 1 cm, 61 N at 2 cm, 153 N at 5 cm, 243 N at 8 cm.
    TILT_GAIN = 0.5: a tilted leg pushes its shank into the sand too, so it bears more (+11 % at
    0.5 rad, +36 % at 1 rad); symmetric in beta.
  * Vertex forces, every one opposing its motion (dissipative):
        P   =  F_b (max(cos psi, 0) + LIFT sin^2 psi)                 (how hard the sand is pressed)
        F_z =  P - PULL F_b max(-cos psi, 0)
        F_x = -MU sin psi P                                           (friction-like drag)
    so pushing straight down gives F_b (the largest normal force of all vertices), dragging
    sideways gives a lift of 0.2 F_b with a drag of MU 0.2 F_b = 0.14 F_b, pulling out is held back
    by 0.05 F_b, and the most horizontal force of any vertex is 0.41 F_b (at psi = 50 deg).
    The drag is friction-like: it scales with how hard the foot presses the sand, not with the
    depth alone. The traction of the polytope (the largest |F_x| it offers at a normal load N, over
    N; traction() below) is 0.90, 0.75, 0.67, 0.62, 0.49 at N = 0.1, 0.2, 0.4, 0.6, 0.8 F_b and
    0 at F_b: sand's friction-like ratio of 0.5-0.8 under load (MU = 0.7), and a lightly loaded
    foot is dragged through the sand easily. Measured the same way, the 15 published RoboSimian
    samples below the surface (../shared/granular/sand_samples) give 0.51-1.77, 0.43-1.32,
    0.40-0.91, 0.34-0.73, 0.15-0.57 (medians 1.52, 0.97, 0.61, 0.43, 0.28), and their most
    horizontal vertex force is 0.24-0.46 of their largest normal force (0.41 here).
    (Until this version the drag was -0.6 F_b sin psi whatever the load, a traction of 4.82, 2.98,
    1.46, 0.89, 0.53: swing feet still in the sand braked the trot harder than the stance feet
    could push, and the planar quadruped drifted backward; see data/granular/README.md.)
  * Torque: pressure on a sphere is normal to its surface and so passes through its centre; the
    model applies the force at the sphere centre. The torque centre is put r = 0.02 m up the leg
    from the foot point (the sphere centre when the leg is upright) and tau_y, the planar moment
    about it, is r ((1 - cos beta) F_x + sin beta F_z): the torque about the sphere centre is then
    zero for every tilt, up to the fit error.
  * Cut-off at the surface (cutoff = 0, cutoff_width = 5 mm): the model is exactly zero above the
    sand and blends in with the format's C^2 quintic step over the first 5 mm.
  * RBF: thin-plate kernel rho^2 log rho with a linear tail, rho = ||diag(30, 1) (f - c_i)||, 40
    centres on the grid phi in {+10, 0, -5, -10, -20, -40, -70, -120} mm x beta in {0, +-0.5, +-1}
    rad; the weights interpolate the formulas above exactly at the centres (the two rows at and
    above the surface interpolate zero, which keeps the fit flat at the surface). s_phi = 30 puts
    the depth rows about as far apart as the angle columns; of the spacings tried (5-50) it gave the
    smallest error with a capacity that is monotone in depth. The script checks, and fails
    otherwise, that on a fine grid (phi in [-12 cm, 0], beta in [-1, 1]) the capacity is monotone
    in depth, the fit stays within 12 N of the formulas (15 % of the capacity below 7.5 mm), and the
    traction of the fitted polytope at 2, 3 and 5 cm (beta = 0, +-0.8) lies in [0.5, 0.8] for
    normal loads of 20-70 % of the capacity and is at most 2 at 10 % (the published samples reach
    1.77 there).
    Beyond 12 cm or |beta| > 1 the model extrapolates (it keeps growing with depth).
"""
import os
import sys

import h5py
import numpy as np

FOOT_RADIUS = 0.02  # m, the quadruped's foot spheres
ROBOT_MASS = 17.4  # kg, models/quadruped/quadruped.urdf
GRAVITY = 9.81
STANDING_SINKAGE = 0.015  # m, where one foot carries a quarter of the weight
TILT_GAIN = 0.5
MU = 0.7  # friction-like ratio of the drag to the pressing force P
LIFT = 0.2
PULL = 0.05
VERTEX_COUNT = 26
TORQUE_CENTRE = FOOT_RADIUS  # m up the leg from the foot point
CUTOFF = 0.0
CUTOFF_WIDTH = 0.005
SCALING = np.array([30.0, 1.0])  # s_phi, s_beta
CENTRE_DEPTHS = [0.01, 0.0, -0.005, -0.01, -0.02, -0.04, -0.07, -0.12]  # phi, m
CENTRE_ANGLES = [-1.0, -0.5, 0.0, 0.5, 1.0]  # beta, rad
UNITS = "phi: m, beta: rad; F_x, F_z: N; tau_y: N m"

DIRECTIONS = 2.0 * np.pi * np.arange(VERTEX_COUNT) / VERTEX_COUNT  # psi_j


def buried_area(sinkage):
    """Horizontal cross-section of the buried part of the foot sphere, m^2."""
    d = np.minimum(sinkage, FOOT_RADIUS)
    return np.pi * (2.0 * FOOT_RADIUS * d - d * d)


SIGMA_Z = ROBOT_MASS * GRAVITY / 4.0 / (STANDING_SINKAGE * buried_area(STANDING_SINKAGE))  # N/m^3


def bearing_capacity(phi, beta):
    sinkage = max(0.0, -phi)
    return SIGMA_Z * sinkage * buried_area(sinkage) * (1.0 + TILT_GAIN * np.sin(beta) ** 2)


def target_wrenches(phi, beta):
    """The 3K planar wrench components at (phi, beta): vertex j in entries 3j..3j+2 = (F_x, F_z, tau_y)."""
    fb = bearing_capacity(phi, beta)
    s, c = np.sin(DIRECTIONS), np.cos(DIRECTIONS)
    pressing = fb * (np.maximum(c, 0.0) + LIFT * s * s)
    fz = pressing - PULL * fb * np.maximum(-c, 0.0)
    fx = -MU * s * pressing
    tau = TORQUE_CENTRE * ((1.0 - np.cos(beta)) * fx + np.sin(beta) * fz)
    return np.stack([fx, fz, tau], axis=1).reshape(-1)


def thin_plate(r2):
    """rho^2 log rho from rho^2, 0 at rho = 0 (as in contact_models/rbf_function.cpp)."""
    out = np.zeros_like(r2)
    positive = r2 > 0.0
    out[positive] = 0.5 * r2[positive] * np.log(r2[positive])
    return out


def fit(centres, values):
    """Exact thin-plate interpolation with a linear tail: returns weights (N x 3K), polynomial (3 x 3K)."""
    n = len(centres)
    diff = (centres[:, None, :] - centres[None, :, :]) * SCALING
    kernel = thin_plate((diff**2).sum(axis=-1))
    tail = np.column_stack([np.ones(n), centres])
    system = np.block([[kernel, tail], [tail.T, np.zeros((3, 3))]])
    rhs = np.vstack([values, np.zeros((3, values.shape[1]))])
    solution = np.linalg.solve(system, rhs)
    return solution[:n], solution[n:]


def evaluate(centres, weights, polynomial, phi, beta):
    """The model's planar wrenches before the cut-off step, as RbfFunction computes them."""
    diff = (np.array([phi, beta]) - centres) * SCALING
    return thin_plate((diff**2).sum(axis=-1)) @ weights + np.array([1.0, phi, beta]) @ polynomial


def cutoff_step(phi):
    """The format's C^2 quintic step: 1 below cutoff - width, 0 above cutoff."""
    t = min(max((CUTOFF - phi) / CUTOFF_WIDTH, 0.0), 1.0)
    return t**3 * (10.0 - 15.0 * t + 6.0 * t * t)


def traction(vertices, load):
    """Largest |F_x| / load over the polygon hull(vertices (K x 2: F_x, F_z), origin) at F_z = load.

    The hull's widest point at a height lies on a hull edge, i.e. on a segment between two of the
    points, and every such segment lies in the hull: the maximum over all pairs is exact."""
    points = np.vstack([vertices, [0.0, 0.0]])
    best = 0.0
    for a in points:
        for b in points:
            if a[1] == load:
                best = max(best, abs(a[0]))
            elif (a[1] - load) * (b[1] - load) < 0.0:
                t = (load - a[1]) / (b[1] - a[1])
                best = max(best, abs(a[0] + t * (b[0] - a[0])))
    return best / load


def check(centres, weights, polynomial):
    """Fails unless the fit is monotone in depth and close to the formulas; prints a summary."""
    worst_abs, worst_rel = 0.0, 0.0
    for beta in np.linspace(-1.0, 1.0, 21):
        previous = -np.inf
        for phi in np.linspace(0.0, -0.12, 241):
            model = evaluate(centres, weights, polynomial, phi, beta) * cutoff_step(phi)
            exact = target_wrenches(phi, beta) * cutoff_step(phi)
            capacity = model[1::3].max()
            if capacity < previous - 1e-9:
                sys.exit(f"check failed: capacity decreases with depth at phi={phi:.4f}, beta={beta:.2f}")
            previous = capacity
            error = np.abs(model - exact).max()
            worst_abs = max(worst_abs, error)
            if phi <= -0.0075:
                worst_rel = max(worst_rel, error / exact[1::3].max())
    if worst_abs > 12.0 or worst_rel > 0.15:
        sys.exit(f"check failed: fit error {worst_abs:.2f} N, {100 * worst_rel:.1f} % of the capacity")
    shares = [0.1, 0.2, 0.4, 0.6, 0.7, 0.8]
    table = []
    for depth in [0.02, 0.03, 0.05]:
        for beta in [-0.8, 0.0, 0.8]:
            planar = (evaluate(centres, weights, polynomial, -depth, beta) * cutoff_step(-depth)).reshape(-1, 3)
            capacity = planar[:, 1].max()
            row = [traction(planar[:, :2], share * capacity) for share in shares]
            if min(row[1:5]) < 0.5 or max(row[1:5]) > 0.8 or row[0] > 2.0:
                sys.exit(f"check failed: traction {np.round(row, 2)} at depth {depth}, beta {beta} "
                         f"(loads {shares} of the capacity)")
            table.append((depth, beta, row))
    print(f"fit error vs the formulas: at most {worst_abs:.2f} N; {100 * worst_rel:.1f} % of the capacity below 7.5 mm")
    print("capacity (largest vertex F_z, N):  depth   beta=0   beta=0.5   beta=1")
    for depth in [0.005, 0.01, 0.015, 0.02, 0.03, 0.05, 0.08]:
        row = [evaluate(centres, weights, polynomial, -depth, b)[1::3].max() * cutoff_step(-depth) for b in (0, 0.5, 1)]
        print(f"{'':35s}{100 * depth:4.1f} cm  {row[0]:7.1f}  {row[1]:8.1f}  {row[2]:8.1f}")
    print("traction (largest |F_x| / F_z of the fitted polytope) at normal loads of " +
          ", ".join(f"{share:g}" for share in shares) + " x the capacity:")
    for depth, beta, row in table:
        print(f"    {100 * depth:3.0f} cm, beta = {beta:+.1f}:  " + "  ".join(f"{r:.2f}" for r in row))


def write(path, centres, weights, polynomial):
    """The project's HDF5 RBF format, version 1 (contact_models/rbf_function.hpp), written atomically."""
    strings = h5py.string_dtype("utf-8")
    partial = path + ".partial"
    with h5py.File(partial, "w", libver="earliest", track_order=False) as f:
        f.attrs["nmdp_model"] = "rbf"
        group = f.create_group("rbf")
        for name, value in [("format_version", 1.0), ("epsilon", 1.0), ("torque_centre", TORQUE_CENTRE),
                            ("cutoff", CUTOFF), ("cutoff_width", CUTOFF_WIDTH)]:
            group.attrs.create(name, value, dtype=np.float64)
        group.attrs["units"] = UNITS
        group.attrs["description"] = ("hand-made soft sand for the nmdp quadruped (17.4 kg, 2 cm feet): "
                                      "see scripts/make_handmade_sand_model.py")
        datasets = [("kernel", np.array(["thin_plate"], dtype=object), strings),
                    ("centres", centres, np.float64), ("weights", weights, np.float64),
                    ("scaling", SCALING, np.float64), ("polynomial", polynomial, np.float64),
                    ("feature_names", np.array(["phi", "beta"], dtype=object), strings)]
        for name, data, dtype in datasets:
            group.create_dataset(name, data=data, dtype=dtype, track_times=False)
    os.replace(partial, path)


def main():
    repo = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    path = sys.argv[1] if len(sys.argv) > 1 else os.path.join(repo, "data", "granular", "handmade_sand_rbf.h5")
    centres = np.array([(phi, beta) for phi in CENTRE_DEPTHS for beta in CENTRE_ANGLES])
    values = np.array([target_wrenches(phi, beta) for phi, beta in centres])
    weights, polynomial = fit(centres, values)
    check(centres, weights, polynomial)
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    write(path, centres, weights, polynomial)
    print(f"wrote {path}: {len(centres)} centres, {VERTEX_COUNT} vertices, sigma_z = {SIGMA_Z:.4g} N/m^3")


if __name__ == "__main__":
    main()
