#!/usr/bin/python3
"""Heading and line of the default floating-base trot: a markdown table for docs/notes.

Runs the quadruped, A1 and Solo-12 trotting on rigid flat ground (and the quadruped on the planar
RFT sand model, with the default trot and with the sand scene's) on a floating base for 10 s at dt = 10, 25
and 50 ms (--dts), with the scene's integrator or each of --methods, with the heading feedback on
and off (--feedback), and prints per run the forward distance along the start heading, |yaw| at the end and
the largest, the lateral offset from the start line at the end (and the largest) over the
forward distance, and the largest |roll|.

    scripts/trot_heading_table.py --nmdp build/nmdp [--duration 10] [--dts 0.01,0.025,0.05]
        [--methods ne-pgm,pbd-pgm] [--feedback on,off] [--cases 0,1,2]

A run whose trunk tilts (|roll| or |pitch|) over 0.5 rad reads "fell at <t> s" in the status column.
"""
import argparse
import pathlib
import subprocess
import sys
import tempfile

import h5py
import numpy as np

CASES = [
    ("quadruped, rigid", "models/scenes/quadruped_trot_flat.json", []),
    ("A1, rigid", "models/scenes/a1_trot_flat.json", []),
    ("Solo-12, rigid", "models/scenes/evaluation/solo12_trot_flat.json", []),
    # The sand scene's model (data/granular/rft_quadruped_rbf.h5, no lateral force) with the default
    # trot and integrator, then with the scene's own gait and method (stride 0.15, step 0.12, pbd-pgm).
    ("quadruped, planar RFT sand", "models/scenes/quadruped_trot_sand.json",
     ["robot.base=floating", 'integrator={"method": "ne-pgm"}', 'controller.gait={"type": "trot"}']),
    ("quadruped, planar RFT sand, the scene's gait", "models/scenes/quadruped_trot_sand.json", ["robot.base=floating"]),
]


def measure(path):
    with h5py.File(path, "r") as f:
        n = int(f["rows"][()]) if "rows" in f else int(f["steps"][()]) if "steps" in f else len(f["time"])
        pos = np.asarray(f["base/position"][:n], float)
        yaw = np.unwrap(np.asarray(f["base/rpy"][:n, 2], float))
        roll_max = float(np.max(np.abs(f["base/rpy"][:n, 0])))
        tilt = np.max(np.abs(np.asarray(f["base/rpy"][:n, :2], float)), axis=1)
        time = np.asarray(f["time"][:n], float)
        status = f["status"][()] if "status" in f else b"?"
    status = status.decode() if isinstance(status, bytes) else str(status)
    if np.any(tilt > 0.5):
        status = f"fell at {time[np.argmax(tilt > 0.5)]:.2f} s"
    heading = np.array([np.cos(yaw[0]), np.sin(yaw[0])])
    left = np.array([-heading[1], heading[0]])
    d = pos[:, :2] - pos[0, :2]
    forward, lateral = d @ heading, d @ left
    yaw = yaw - yaw[0]
    return dict(status=status, forward=forward[-1], yaw_end=yaw[-1], yaw_max=np.max(np.abs(yaw)), roll_max=roll_max,
                lat_end=lateral[-1], lat_max=np.max(np.abs(lateral)))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--nmdp", default="build/nmdp")
    parser.add_argument("--duration", type=float, default=10.0)
    parser.add_argument("--dts", default="0.01,0.025,0.05")
    parser.add_argument("--methods", default="", help="comma-separated integrator methods, default the scene's")
    parser.add_argument("--feedback", default="on,off", help="on, off or both (default)")
    parser.add_argument("--cases", default="", help="comma-separated case numbers (0-4), default all")
    args = parser.parse_args()
    cases = [CASES[int(i)] for i in args.cases.split(",")] if args.cases else CASES
    methods = args.methods.split(",") if args.methods else [None]
    feedbacks = [{"on": "true", "off": "false"}[x] for x in args.feedback.split(",")]
    print("| robot, ground | method | dt ms | feedback | forward m | yaw end rad | max abs yaw rad | lateral end / forward "
          "| max abs lateral / forward | max abs roll rad | status |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for label, scene, extra in cases:
            if not pathlib.Path(scene).exists():
                print(f"| {label} | — | — | scene {scene} absent |")
                continue
            for method, dt, feedback in ((m, float(d), fb) for m in methods for d in args.dts.split(",") for fb in feedbacks):
                out = pathlib.Path(tmp) / "run.h5"
                sets = extra + [f"integrator.dt={dt}", f"duration={args.duration}",
                                f"controller.gait.heading_feedback={feedback}"]
                if method:
                    sets.append(f"integrator.method={method}")
                cmd = [args.nmdp, "simulate", scene, "--out", str(out), "--quiet"]
                for s in sets:
                    cmd += ["--set", s]
                run = subprocess.run(cmd, capture_output=True, text=True)
                if not out.exists():
                    print(f"| {label} | {method or 'scene'} | {dt * 1e3:g} | {feedback} | failed (exit {run.returncode}): {run.stderr.strip()[:120]} |")
                    continue
                m = measure(out)
                fwd = m["forward"]
                print(f"| {label} | {method or 'scene'} | {dt * 1e3:g} | {'on' if feedback == 'true' else 'off'} | {fwd:.3f} | {m['yaw_end']:+.3f} | "
                      f"{m['yaw_max']:.3f} | {m['lat_end'] / fwd:+.1%} | {m['lat_max'] / abs(fwd):.1%} | {m['roll_max']:.2f} | {m['status'][:40]} |")
                out.unlink()
                sys.stdout.flush()


if __name__ == "__main__":
    main()
