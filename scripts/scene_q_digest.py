#!/usr/bin/python3
"""Run every scene under models/scenes with an nmdp binary and print one digest of /q per scene.

Behaviour-preserving changes (refactors) must leave every digest unchanged on one machine:

    scripts/scene_q_digest.py --nmdp build/nmdp > before.txt   # on the commit before the change
    scripts/scene_q_digest.py --nmdp build/nmdp > after.txt    # on the change
    diff before.txt after.txt
"""
import argparse
import hashlib
import pathlib
import subprocess
import sys
import tempfile

import h5py
import numpy as np


def digest(path):
    with h5py.File(path, "r") as f:
        q = np.ascontiguousarray(f["q"][...])
    return hashlib.sha256(q.tobytes()).hexdigest()[:16], q.shape


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--nmdp", default="build/nmdp", help="the nmdp executable")
    parser.add_argument("--scenes", default="models/scenes", help="folder of scene files (searched recursively)")
    args = parser.parse_args()
    scenes = sorted(pathlib.Path(args.scenes).rglob("*.json"))
    failed = False
    with tempfile.TemporaryDirectory() as tmp:
        for scene in scenes:
            out = pathlib.Path(tmp) / (scene.stem + ".h5")
            run = subprocess.run([args.nmdp, "simulate", str(scene), "--out", str(out), "--quiet"],
                                 capture_output=True, text=True)
            if run.returncode != 0 or not out.exists():
                print(f"{scene}: failed (exit {run.returncode}): {run.stderr.strip()[:200]}")
                failed = True
                continue
            value, shape = digest(out)
            print(f"{scene}: {value} {shape[0]}x{shape[1]}")
            sys.stdout.flush()
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
