#!/usr/bin/python3
"""A sweep of short runs on a LocalCluster against the same runs one by one in a shell loop.

The sweep: the sand trot (models/scenes/quadruped_trot_sand.json) for --duration s at a grid of
--runs points (gait period x stride length), `nmdp sweep --workers N`, timed from the command's
start to its end (the LocalCluster's start, the key check, every run and the index included). The
loop: the same `nmdp simulate` commands (the same --set arguments) in a bash `for` loop, one after
another. Both write every run; their /q are compared bit for bit, so the two did the same work.
Target: the sweep with 2 workers at least 1.8x as fast as the loop on the 2-core machine.

Usage (after building nmdp and its Python package):
    flock /tmp/nmdp-cpu.lock /usr/bin/python3 bench/python/bench_sweep.py [--runs 200] [--duration 0.5]
        [--workers 2] [--nmdp build/nmdp] [--keep DIR]
"""
import argparse
import json
import os
import shlex
import subprocess
import sys
import tempfile
import time

import h5py

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
SCENE = os.path.join(ROOT, "models", "scenes", "quadruped_trot_sand.json")


def grid(n):
    """n grid points: periods 0.40, 0.41, ... by stride lengths 0.10, 0.11, ... (20 strides at most)."""
    strides = min(n, 20)
    periods = -(-n // strides)
    return {"controller.gait.period": [round(0.4 + 0.01 * i, 4) for i in range(periods)],
            "controller.gait.stride_length": [round(0.1 + 0.005 * i, 4) for i in range(strides)]}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=200)
    ap.add_argument("--duration", type=float, default=0.5)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--nmdp", default=os.path.join(ROOT, "build", "nmdp"))
    ap.add_argument("--keep", default=None, help="write the runs here and keep them (default: a temporary folder)")
    a = ap.parse_args()
    nmdp = os.path.abspath(a.nmdp)
    sys.path.insert(0, os.path.join(os.path.dirname(nmdp), "python"))
    from nmdp.sweep import spec

    folder = a.keep or tempfile.mkdtemp(prefix="bench-sweep-")
    os.makedirs(folder, exist_ok=True)
    sweep_file = os.path.join(folder, "sweep.json")
    with open(sweep_file, "w") as f:
        json.dump({"scene": SCENE, "base": {"duration": a.duration}, "grid": grid(a.runs)}, f)
    runs = spec.load(sweep_file).runs[:a.runs]
    if len(spec.load(sweep_file).runs) != a.runs:  # a grid larger than --runs: list the first --runs instead
        with open(sweep_file, "w") as f:
            json.dump({"scene": SCENE, "runs": [r.overrides for r in runs]}, f)

    loop_dir = os.path.join(folder, "loop")
    os.makedirs(loop_dir, exist_ok=True)
    script = os.path.join(folder, "loop.sh")
    with open(script, "w") as f:
        f.write("set -e\n")
        for r in runs:
            sets = " ".join(f"--set {shlex.quote(s)}" for s in r.sets())
            f.write(f"{shlex.quote(nmdp)} simulate {shlex.quote(SCENE)} {sets} --out {loop_dir}/{r.id}.h5 --quiet\n")

    print(f"{a.runs} runs of the sand trot for {a.duration} s; load before: {os.getloadavg()[0]:.2f}", flush=True)
    start = time.monotonic()
    subprocess.run(["bash", script], check=True)
    loop = time.monotonic() - start
    print(f"shell loop:               {loop:7.1f} s ({loop / a.runs * 1000:.0f} ms a run)", flush=True)

    out = os.path.join(folder, "sweep")
    start = time.monotonic()
    subprocess.run([nmdp, "sweep", sweep_file, "--workers", str(a.workers), "--out", out, "--quiet"], check=True)
    swept = time.monotonic() - start
    print(f"nmdp sweep, {a.workers} workers:   {swept:7.1f} s ({swept / a.runs * 1000:.0f} ms a run)")
    print(f"speed-up: {loop / swept:.2f}x (target 1.8x with 2 workers); load after: {os.getloadavg()[0]:.2f}")

    for r in runs:
        with h5py.File(os.path.join(loop_dir, r.id + ".h5"), "r") as x, \
                h5py.File(os.path.join(out, "runs", r.id + ".h5"), "r") as y:
            if x["q"][()].tobytes() != y["q"][()].tobytes():
                sys.exit(f"run {r.id}: the sweep's /q differs from the loop's")
    print(f"all {a.runs} runs: the same /q bit for bit; files in {folder}" if a.keep else
          f"all {a.runs} runs: the same /q bit for bit")
    if not a.keep:
        subprocess.run(["rm", "-rf", folder], check=True)


if __name__ == "__main__":
    main()
