"""The runs of the evaluation: which ones (case × variant × method × dt), their `nmdp simulate`
commands, and running them a few at a time with a manifest of what ran (command, exit, time)."""
import concurrent.futures
import json
import os
import re
import subprocess
import time

METHODS = ["ne-pgm", "pbd-pgm"]  # the default method and its PBD twin
DTS = [0.001, 0.005, 0.01, 0.02, 0.05]
REFERENCE_DT = 0.001
DEFAULT = ""  # the variant label of the rows with the scene defaults


def slug(label):
    return re.sub(r"[^a-z0-9]+", "-", label.lower()).strip("-")[:40] or "default"


def plan(cases, variants_of, methods=METHODS, dts=DTS):
    """Every run: dict(case, variant, sets, method, dt, key). variants_of(case) gives the labelled
    variants to add ({label: [--set ...]}); the defaults' rows come first."""
    runs = []
    for c in cases:
        for label, sets in [(DEFAULT, [])] + list(variants_of(c).items()):
            for method in methods:
                for dt in dts:
                    name = f"{method}_dt{round(dt * 1000):03d}ms"
                    key = f"{c['id']}/{slug(label) if label else 'default'}/{name}"
                    runs.append(dict(case=c["id"], variant=label, sets=list(sets), method=method, dt=dt, key=key))
    keys = [r["key"] for r in runs]
    if len(set(keys)) != len(keys):
        raise ValueError("two variants of a case share a file name: " + ", ".join(sorted({k for k in keys if keys.count(k) > 1})))
    return runs


def command(nmdp, scene_path, run, common_sets, duration, out_path):
    """`nmdp simulate` for one run: the case's scene, the evaluation-wide --set settings, the
    variant's, then the method and dt."""
    cmd = [nmdp, "simulate", scene_path]
    for s in list(common_sets) + run["sets"]:
        cmd += ["--set", s]
    cmd += ["--set", f"integrator.method={run['method']}", "--set", f"integrator.dt={run['dt']:g}",
            "--set", f"duration={duration:g}", "--out", out_path, "--quiet"]
    return cmd


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
    with concurrent.futures.ThreadPoolExecutor(max_workers=workers) as pool:
        for done, future in enumerate(concurrent.futures.as_completed([pool.submit(_execute, j) for j in jobs]), 1):
            r = future.result()
            manifest[r["key"]] = r
            flag = "" if r["rc"] == 0 else f"  [exit {r['rc']}]"
            log(f"[{done}/{len(jobs)} {time.monotonic() - start:5.0f} s] {r['key']} {r['elapsed']:.1f} s{flag}")
            if done % 10 == 0 or done == len(jobs):
                with open(manifest_path, "w") as f:
                    json.dump(manifest, f, indent=1)
    return time.monotonic() - start
