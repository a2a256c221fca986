"""Which runs the evaluation makes: its cases (one scene file each under models/scenes/evaluation/,
read with every key the file leaves out at the scene default), the labelled variants of each case,
and every run as case × variant × method × dt with its `nmdp simulate` command."""
import json
import os
import re

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
CASE_DIR = os.path.join(ROOT, "models", "scenes", "evaluation")

METHODS = ["ne-pgm", "pbd-pgm"]  # the default method and its PBD twin
DTS = [0.001, 0.005, 0.01, 0.02, 0.025, 0.05]
DEFAULT = ""  # the variant label of the rows with the scene defaults

# Keys a case's scene may not set: they would make it a tuned case rather than one with the
# defaults. A labelled variant may set them (a variant is an extra row, never the verdict's).
TUNING_KEYS = ("integrator", "controller.kp", "controller.kd", "controller.tau_ff",
               "controller.gait.swing_profile", "controller.gait.ground_speed_share", "controller.gait.start_ramp",
               "controller.gait.heading_feedback")

# The discretization's levers, on every case: the paper's method (its K, its fixed step), the fixed
# step alone, and the second order with and without error control.
SOLVER_VARIANTS = {
    "the paper's method (K = full-body, no error control)": ["integrator.kinetic_energy=full-body",
                                                             "integrator.accuracy=0"],
    "no error control (accuracy 0)": ["integrator.accuracy=0"],
    "order 2": ["integrator.order=2"],
    "order 2, no error control": ["integrator.order=2", "integrator.accuracy=0"],
}

# The K, gains, swing and start ramp the former evaluation ran with, kept as variants for the record.
_PD_K = "integrator.kinetic_energy=full-body-pd"
_TUNED = "tuned (the former evaluation's K, gains, swing and ramp)"
_QUADRUPED_GAINS = [_PD_K, "controller.kp=1800", "controller.kd=3", "controller.gait.swing_profile=ground_speed",
                    "controller.gait.start_ramp=0.5"]
_ROBOSIMIAN_GAINS = [_PD_K, "controller.kp=10000", "controller.kd=10", "controller.gait.swing_profile=ground_speed",
                     "controller.gait.start_ramp=1"]

# Per case (the scene file's name): the robot's name on the page and the case's own variants, in
# the order the page lists the cases.
CASES = {
    "quadruped_trot_flat": ("quadruped", {"tuned (the former evaluation's K, gains, swing and ramp; planar base)":
                                          ["robot.base=planar"] + _QUADRUPED_GAINS}),
    "a1_trot_flat": ("A1", {"kd = 3, K = full-body-pd (bench_mujoco's damped scenario)": [_PD_K, "controller.kd=3"]}),
    "solo12_trot_flat": ("Solo-12", {}),
    "robosimian_walk_rigid": ("RoboSimian", {_TUNED: _ROBOSIMIAN_GAINS}),
    "robosimian_walk_sand": ("RoboSimian", {_TUNED: _ROBOSIMIAN_GAINS}),
    "quadruped_trot_sand": ("quadruped", {_TUNED: _QUADRUPED_GAINS}),
    "quadruped_trot_sand3d": ("quadruped", {}),
    "a1_trot_sand3d": ("A1", {}),
    "solo12_trot_sand3d": ("Solo-12", {}),
}

# The straight-walk study on 3-D sand: the floating-base cases below at WALK_DTS with the default
# method, each beside the same robot on a planar base with the planar model fitted from the same RFT
# medium and foot (the variant PLANAR_TWIN, an extra row of the step-size tables too).
WALK_CASES = ["quadruped_trot_sand3d", "a1_trot_sand3d", "solo12_trot_sand3d"]
WALK_DTS = [0.01, 0.025, 0.05]
PLANAR_TWIN = "planar base, planar model of the same medium"
_PLANAR_MODEL = "../../../data/granular/rft3d_quadruped_planar_rbf.h5"  # relative to the case file
_PLANAR_TWIN_SETS = ["robot.base=planar", 'contacts.model={"type": "rbf", "file": "%s"}' % _PLANAR_MODEL]
for _case in WALK_CASES:
    CASES[_case][1][PLANAR_TWIN] = _PLANAR_TWIN_SETS


def load_case(path, robot=None, variants=None):
    """A case from its scene file: id, path, robot, base, ground (sand for any model but the
    Coulomb cone), the scene (a dict, as written), the files it reads (absolute) and its variants."""
    with open(path) as f:
        scene = json.load(f)
    case_id = os.path.splitext(os.path.basename(path))[0]
    folder = os.path.dirname(os.path.abspath(path))
    model = scene.get("contacts", {}).get("model", {})
    files = [os.path.normpath(os.path.join(folder, scene["robot"]["urdf"]))]
    if "file" in model:
        files.append(os.path.normpath(os.path.join(folder, model["file"])))
    return dict(id=case_id, path=os.path.abspath(path), robot=robot or case_id.split("_")[0],
                base=scene["robot"].get("base", "floating"),
                ground="rigid" if model.get("type", "coulomb") == "coulomb" else "sand",
                scene=scene, files=files, variants={**SOLVER_VARIANTS, **(variants or {})})


def all_cases(folder=CASE_DIR):
    """Every scene file in `folder`: the known cases first, in CASES's order, then any other."""
    names = sorted(os.path.splitext(n)[0] for n in os.listdir(folder) if n.endswith(".json"))
    ordered = [n for n in CASES if n in names] + [n for n in names if n not in CASES]
    return [load_case(os.path.join(folder, n + ".json"), *CASES.get(n, (None, None))) for n in ordered]


def missing(case):
    """Why the case cannot run here (its robot or sand model absent), or None."""
    absent = [p for p in case["files"] if not os.path.exists(p)]
    return f"absent: {', '.join(absent)}" if absent else None


def check_defaults(case):
    """The case's own scene sets none of TUNING_KEYS (raises ValueError naming the key)."""
    for key in TUNING_KEYS:
        node = case["scene"]
        for part in key.split("."):
            node = node.get(part) if isinstance(node, dict) else None
        if node is not None:
            raise ValueError(f"case {case['id']}: its scene sets {key}, which the evaluation leaves at the default")


def slug(label):
    return re.sub(r"[^a-z0-9]+", "-", label.lower()).strip("-")[:40] or "default"


def runs(cases, variants_of, methods=METHODS, dts=DTS):
    """Every run: dict(case, variant, sets, method, dt, key). variants_of(case) gives the labelled
    variants to add ({label: [--set ...]}); the defaults' rows come first."""
    out = []
    for c in cases:
        for label, sets in [(DEFAULT, [])] + list(variants_of(c).items()):
            for method in methods:
                for dt in dts:
                    name = f"{method}_dt{round(dt * 1000):03d}ms"
                    key = f"{c['id']}/{slug(label) if label else 'default'}/{name}"
                    out.append(dict(case=c["id"], variant=label, sets=list(sets), method=method, dt=dt, key=key))
    keys = [r["key"] for r in out]
    if len(set(keys)) != len(keys):
        raise ValueError("two variants of a case share a file name: " + ", ".join(sorted({k for k in keys if keys.count(k) > 1})))
    return out


def command(nmdp, scene_path, run, common_sets, duration, out_path):
    """`nmdp simulate` for one run: the case's scene, the evaluation-wide --set settings, the
    variant's, then the method and dt."""
    cmd = [nmdp, "simulate", scene_path]
    for s in list(common_sets) + run["sets"]:
        cmd += ["--set", s]
    cmd += ["--set", f"integrator.method={run['method']}", "--set", f"integrator.dt={run['dt']:g}",
            "--set", f"duration={duration:g}", "--out", out_path, "--quiet"]
    return cmd
