"""The evaluation's cases: each a scene made at run time from a robot and the keys that define the
case (base, ground, gait), everything else at the scene defaults. Robots in ../shared are read in
place: the generated scene names their URDF by absolute path and is written into the results
folder, never into the repository."""
import json
import os

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
SCENES = os.path.join(ROOT, "models", "scenes")
SHARED = os.path.abspath(os.path.join(ROOT, "..", "shared"))

# Keys a case may not set: they would make it a tuned case rather than one with the defaults. A case's
# labelled variant may set them (a variant is an extra row, never the verdict's).
TUNING_KEYS = ("integrator", "controller.kp", "controller.kd", "controller.tau_ff",
               "controller.gait.swing_profile", "controller.gait.ground_speed_share", "controller.gait.start_ramp")


def _scene_keys(name):
    """A repository scene's keys without its integrator section, duration and output (so the scene
    defaults hold), with its paths made absolute."""
    path = os.path.join(SCENES, name)
    with open(path) as f:
        scene = json.load(f)
    for key in ("integrator", "duration", "output"):
        scene.pop(key, None)
    base = os.path.dirname(path)
    scene["robot"]["urdf"] = os.path.normpath(os.path.join(base, scene["robot"]["urdf"]))
    model = scene.get("contacts", {}).get("model", {})
    if "file" in model:
        model["file"] = os.path.normpath(os.path.join(base, model["file"]))
    return scene


def _floating_trot(urdf):
    return {"robot": {"urdf": urdf, "base": "floating"}, "controller": {"gait": {"type": "trot"}}}


def _robosimian(ground):
    # The paper's set-up: planar base (x, z, pitch), joints 2, 4, 6 of each limb, the others locked
    # at 0, and a bent nominal pose (its limbs stretch out level at q = 0); all kept from the
    # repository's scene, which names the URDF in ../shared.
    scene = _scene_keys("robosimian_walk_planar.json")
    if ground == "sand":
        scene["contacts"]["model"] = {"type": "rbf", "file": os.path.join(SHARED, "granular", "robosimian_sand_rbf")}
    return scene


# The discretization's levers, on every case: the paper's method (its K, its fixed step), the fixed
# step alone, and the second order with and without error control.
SOLVER_VARIANTS = {
    "the paper's method (K = full-body, no error control)": ["integrator.kinetic_energy=full-body",
                                                             "integrator.accuracy=0"],
    "no error control (accuracy 0)": ["integrator.accuracy=0"],
    "order 2": ["integrator.order=2"],
    "order 2, no error control": ["integrator.order=2", "integrator.accuracy=0"],
}


def all_cases():
    """Every case: id, robot, base, ground, the scene (a dict), the files it needs, and labelled
    variants ({label: [--set ...]}) that become extra rows (unless --no-variants)."""
    # The K the former evaluation ran with (now the default; kept in its variants for the record).
    pd_k = "integrator.kinetic_energy=full-body-pd"
    quadruped_gains = [pd_k, "controller.kp=1800", "controller.kd=3", "controller.gait.swing_profile=ground_speed",
                       "controller.gait.start_ramp=0.5"]
    robosimian_gains = [pd_k, "controller.kp=10000", "controller.kd=10", "controller.gait.swing_profile=ground_speed",
                        "controller.gait.start_ramp=1"]
    cases = [
        dict(id="quadruped_trot_flat", robot="quadruped", base="floating", ground="rigid",
             scene=_scene_keys("quadruped_trot_flat.json"),
             variants={"tuned (the former evaluation's K, gains, swing and ramp; planar base)":
                       ["robot.base=planar"] + quadruped_gains}),
        dict(id="a1_trot_flat", robot="A1", base="floating", ground="rigid",
             scene=_floating_trot(os.path.join(SHARED, "robots", "a1", "urdf", "a1.urdf")),
             variants={"kd = 3, K = full-body-pd (bench_mujoco's damped scenario)": [pd_k, "controller.kd=3"]}),
        dict(id="solo12_trot_flat", robot="Solo-12", base="floating", ground="rigid",
             scene=_floating_trot(os.path.join(SHARED, "robots", "solo12", "urdf", "solo12.urdf")),
             variants={}),
        dict(id="robosimian_walk_rigid", robot="RoboSimian", base="planar", ground="rigid",
             scene=None, variants={"tuned (the former evaluation's K, gains, swing and ramp)": robosimian_gains}),
        dict(id="robosimian_walk_sand", robot="RoboSimian", base="planar", ground="sand",
             scene=None, variants={"tuned (the former evaluation's K, gains, swing and ramp)": robosimian_gains}),
        dict(id="quadruped_trot_sand", robot="quadruped", base="planar", ground="sand",
             scene=_scene_keys("quadruped_trot_sand.json"),
             variants={"tuned (the former evaluation's K, gains, swing and ramp)": quadruped_gains}),
    ]
    for c in cases:
        c["variants"] = {**SOLVER_VARIANTS, **c["variants"]}
        if c["robot"] == "RoboSimian":
            try:
                c["scene"] = _robosimian(c["ground"])
            except OSError:
                c["scene"] = None
    return cases


def files_of(scene):
    """The files a scene reads (to skip a case whose robot or sand model is absent)."""
    files = [scene["robot"]["urdf"]]
    model = scene.get("contacts", {}).get("model", {})
    if "file" in model:
        files.append(model["file"])
    return files


def missing(case):
    """Why the case cannot run here (its robot or sand model absent), or None."""
    if case["scene"] is None:
        return f"its scene's robot is absent ({SHARED} not found)"
    absent = [p for p in files_of(case["scene"]) if not os.path.exists(p)]
    return f"absent: {', '.join(absent)}" if absent else None


def check_defaults(case):
    """The case's own scene sets none of TUNING_KEYS (raises ValueError naming the key)."""
    for key in TUNING_KEYS:
        node = case["scene"]
        for part in key.split("."):
            node = node.get(part) if isinstance(node, dict) else None
        if node is not None:
            raise ValueError(f"case {case['id']}: its scene sets {key}, which the evaluation leaves at the default")


def write_scene(case, folder):
    """Writes the case's scene as FOLDER/<id>.json and returns its path."""
    os.makedirs(folder, exist_ok=True)
    path = os.path.join(folder, case["id"] + ".json")
    with open(path, "w") as f:
        json.dump(case["scene"], f, indent=1)
    return path
