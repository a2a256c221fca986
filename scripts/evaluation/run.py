"""Running the evaluation's `nmdp simulate` commands a few at a time in a pool of processes, with a
manifest of what ran (command, exit, time), and the commit the runs were made from."""
import concurrent.futures
import json
import os
import subprocess
import time

from .plan import ROOT


def _execute(job):
    os.makedirs(os.path.dirname(job["out"]), exist_ok=True)
    if os.path.exists(job["out"]):
        os.remove(job["out"])
    start = time.monotonic()
    try:
        p = subprocess.run(job["cmd"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, timeout=job["timeout"], text=True)
        rc, err = p.returncode, p.stderr.strip()
    except subprocess.TimeoutExpired:
        rc, err = "timeout", f"killed after {job['timeout']} s"
    return dict(key=job["key"], cmd=job["cmd"], rc=rc, elapsed=time.monotonic() - start, stderr=err[-500:])


def execute(jobs, workers, manifest, manifest_path, log):
    """Runs the jobs (dict key, cmd, out, timeout), `workers` at a time, the finest dt first (the
    longest), recording each in `manifest` (saved to manifest_path as it goes). Returns the wall time."""
    def cost(job):
        dt = float(next(t.split("=", 1)[1] for t in job["cmd"] if t.startswith("integrator.dt=")))
        return -1.0 / dt
    jobs = sorted(jobs, key=cost)
    start = time.monotonic()
    with concurrent.futures.ProcessPoolExecutor(max_workers=workers) as pool:
        for done, future in enumerate(concurrent.futures.as_completed([pool.submit(_execute, j) for j in jobs]), 1):
            r = future.result()
            manifest[r["key"]] = r
            flag = "" if r["rc"] == 0 else f"  [exit {r['rc']}]"
            log(f"[{done}/{len(jobs)} {time.monotonic() - start:5.0f} s] {r['key']} {r['elapsed']:.1f} s{flag}")
            if done % 10 == 0 or done == len(jobs):
                with open(manifest_path, "w") as f:
                    json.dump(manifest, f, indent=1)
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
