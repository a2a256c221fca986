"""Running the evaluation's `nmdp simulate` commands a few at a time through nmdp's sweep library
(nmdp.sweep: one Dask task per run on a LocalCluster, each file written under a temporary name and
renamed when complete), with a manifest of what ran (command, exit, time), and the commit the runs
were made from."""
import json
import os
import subprocess
import sys
import time

from .plan import ROOT


def _sweep_library(nmdp):
    """nmdp.sweep from the build the binary belongs to (its python folder beside it)."""
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(nmdp)), "python"))
    try:
        from nmdp import sweep
    except ImportError as e:
        sys.exit(f"evaluate.py: error: the runs need nmdp's Python package beside {nmdp} (python/nmdp, built with it) "
                 f"and Dask's distributed (Debian: python3-distributed): {e}")
    return sweep


def _job(sweep, job):
    """A sweep job from an `nmdp simulate SCENE --set ... --out FILE --quiet` command: the same scene
    and --set arguments, in the same order."""
    cmd = job["cmd"]
    sets = [cmd[i + 1] for i in range(len(cmd) - 1) if cmd[i] == "--set"]
    return sweep.Job(key=job["key"], scene=cmd[2], sets=sets, out=job["out"])


def execute(jobs, workers, manifest, manifest_path, log, scheduler=None):
    """Runs the jobs (dict key, cmd, out, timeout) on a LocalCluster of `workers` processes (or the
    Dask cluster at `scheduler`), the finest dt first (the longest), recording each in `manifest`
    (saved to manifest_path as it goes). Returns the wall time."""
    def cost(job):
        dt = float(next(t.split("=", 1)[1] for t in job["cmd"] if t.startswith("integrator.dt=")))
        return -1.0 / dt
    jobs = sorted(jobs, key=cost)
    sweep = _sweep_library(jobs[0]["cmd"][0])
    for job in jobs:  # a run that fails now must not leave an older run's file to be measured
        if os.path.exists(job["out"]):
            os.remove(job["out"])
    by_key = {job["key"]: job for job in jobs}
    start = time.monotonic()
    done = 0

    def record(job, result):
        nonlocal done
        done += 1
        rc = result["returncode"] if result["returncode"] is not None else result["status"]  # None: no process ran
        r = dict(key=job.key, cmd=by_key[job.key]["cmd"], rc=rc, elapsed=result["wall"], stderr=result["stderr"])
        manifest[r["key"]] = r
        flag = "" if r["rc"] == 0 else f"  [exit {r['rc']}]"
        log(f"[{done}/{len(jobs)} {time.monotonic() - start:5.0f} s] {r['key']} {r['elapsed']:.1f} s{flag}")
        if done % 10 == 0 or done == len(jobs):
            with open(manifest_path, "w") as f:
                json.dump(manifest, f, indent=1)

    sweep.run_jobs([_job(sweep, j) for j in jobs], jobs[0]["cmd"][0], workers=workers, scheduler=scheduler,
                   timeout=jobs[0]["timeout"],
                   on_result=record)
    return time.monotonic() - start


def git_state():
    """(short commit, whether anything but the page and its figures differs from it)."""
    try:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no", "--", ".", ":!docs/RESULTS.md",
                                ":!docs/figures"], cwd=ROOT, capture_output=True, text=True).stdout.strip()
    except OSError:
        return "unknown", False
    return commit or "unknown", bool(dirty)
