#!/usr/bin/python3
"""The step-size evaluation with the scene defaults: every case at dt = 1, 5, 10, 20, 50 ms with the
default method and its PBD twin, each against the same method's 1 ms run; writes docs/RESULTS.md and
docs/figures/steps_*.png, every claim computed from the runs.

Usage:
    scripts/evaluate.py                         # the evaluation: 10 s runs, page in docs/
    scripts/evaluate.py --duration 0.2          # a smoke run: page and runs in build/evaluation-short/
    scripts/evaluate.py --set integrator.order=2 --set integrator.accuracy=1e-3   # settings for every run
    scripts/evaluate.py --variant "kd 3" controller.kd=3   # extra labelled rows (their own 1 ms reference)
    scripts/evaluate.py --no-variants           # only the defaults' rows, not the cases' built-in variants

Cases (scripts/evaluation/cases.py): the project's quadruped, A1 and Solo-12 trotting on flat ground
with a floating base; RoboSimian walking with the paper's planar base on rigid ground (Coulomb) and on
the published sand model; the quadruped's planar trot on the project's sand model. Every case carries
labelled variants: the paper's method (K = full-body, no error control), no error control, order 2
with and without error control, and for some the former evaluation's gains, swing profile and start
ramp (A1: kd = 3): extra rows against their own 1 ms run, never part of the verdict. Scenes are written
at run time into the results folder from the robot and the keys that define the case; robots in
../shared are read in place, and a case whose files are absent is skipped with a message.

Needs Debian's python3 (h5py, numpy, matplotlib) and a built nmdp (default build/nmdp). Results go to
--out-dir (default build/evaluation, or build/evaluation-short below 10 s): the HDF5 runs, the
generated scenes, manifest.json and rows.json. Never commit them.
"""
import argparse
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from evaluation import cases as case_defs  # noqa: E402
from evaluation import measure, report, runs  # noqa: E402

ROOT = case_defs.ROOT


def git_state():
    try:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no", "--", ".", ":!docs/RESULTS.md",
                                ":!docs/figures"], cwd=ROOT, capture_output=True, text=True).stdout.strip()
    except OSError:
        return "unknown", False
    return commit or "unknown", bool(dirty)


def parse_args(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], epilog=__doc__.split("\n\n", 1)[1],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--duration", type=float, default=10.0, help="simulated seconds per run (default 10; less is a smoke run)")
    ap.add_argument("--set", dest="sets", action="append", default=[], metavar="KEY=VALUE",
                    help="passed to every run as nmdp simulate --set (repeatable), e.g. integrator.order=2")
    ap.add_argument("--variant", nargs="+", action="append", default=[], metavar=("LABEL", "KEY=VALUE"),
                    help="extra labelled rows for every case: LABEL then --set settings")
    ap.add_argument("--no-variants", dest="variants", action="store_false",
                    help="leave out each case's built-in labelled variants (the former evaluation's tuning)")
    ap.add_argument("--cases", default=None, help="comma-separated case ids (default: all)")
    ap.add_argument("--methods", default=",".join(runs.METHODS), help="comma-separated methods (default ne-pgm,pbd-pgm)")
    ap.add_argument("--dts", default=",".join(f"{dt:g}" for dt in runs.DTS),
                    help="comma-separated dt in s; the smallest is the reference (default 0.001,0.005,0.01,0.02,0.05)")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 2, help="runs at a time (default: the number of cores)")
    ap.add_argument("--out-dir", default=None, help="results folder (default build/evaluation, build/evaluation-short below 10 s)")
    ap.add_argument("--docs-dir", default=None, help="where RESULTS.md and figures/ go (default docs/; below 10 s the results folder)")
    ap.add_argument("--nmdp", default=os.path.join(ROOT, "build", "nmdp"), help="the nmdp binary (default build/nmdp)")
    ap.add_argument("--reuse", action="store_true", help="keep runs already made with the same command")
    ap.add_argument("--report-only", action="store_true", help="run nothing; read --out-dir and write the page")
    ap.add_argument("--timeout", type=float, default=1800, help="seconds before a run is killed (default 1800)")
    a = ap.parse_args(argv)
    if a.duration <= 0:
        ap.error("--duration must be positive")
    for v in a.variant:
        if len(v) < 2 or any("=" not in s for s in v[1:]):
            ap.error(f"--variant {' '.join(v)}: give a label and at least one KEY=VALUE")
    if any("=" not in s for s in a.sets):
        ap.error("--set takes KEY=VALUE")
    short = a.duration < 10
    a.out_dir = os.path.abspath(a.out_dir or os.path.join(ROOT, "build", "evaluation-short" if short else "evaluation"))
    a.docs_dir = os.path.abspath(a.docs_dir or (a.out_dir if short else os.path.join(ROOT, "docs")))
    a.nmdp = os.path.abspath(a.nmdp)
    a.methods = a.methods.split(",")
    a.dts = sorted(float(x) for x in a.dts.split(","))
    return a


def main(argv=None):
    a = parse_args(argv)
    log = lambda msg: print(f"evaluate.py: {msg}", file=sys.stderr)  # noqa: E731
    if not a.report_only and not os.access(a.nmdp, os.X_OK):
        sys.exit(f"evaluate.py: error: {a.nmdp} is not an executable (build it with scripts/build.sh, or pass --nmdp)")
    chosen = set(a.cases.split(",")) if a.cases else None
    all_cases = case_defs.all_cases()
    if chosen and chosen - {c["id"] for c in all_cases}:
        sys.exit(f"evaluate.py: error: unknown case(s) {', '.join(sorted(chosen - {c['id'] for c in all_cases}))}; "
                 f"the cases are {', '.join(c['id'] for c in all_cases)}")
    cases, skipped = [], []
    for c in all_cases:
        if chosen and c["id"] not in chosen:
            continue
        why = case_defs.missing(c)
        if why:
            log(f"skipping {c['id']}: {why}")
            skipped.append(f"{c['id']}: {why}")
            continue
        case_defs.check_defaults(c)
        cases.append(c)

    def variants_of(case):
        v = dict(case["variants"]) if a.variants else {}
        v.update({x[0]: x[1:] for x in a.variant})
        return v

    plan = runs.plan(cases, variants_of, a.methods, a.dts)
    os.makedirs(a.out_dir, exist_ok=True)
    manifest_path = os.path.join(a.out_dir, "manifest.json")
    manifest = {}
    if os.path.exists(manifest_path) and (a.reuse or a.report_only):
        with open(manifest_path) as f:
            manifest = json.load(f)
    scene_paths = {c["id"]: case_defs.write_scene(c, os.path.join(a.out_dir, "scenes")) for c in cases}
    jobs = []
    for r in plan:
        r["out"] = os.path.join(a.out_dir, "runs", r["key"] + ".h5")
        cmd = runs.command(a.nmdp, scene_paths[r["case"]], r, a.sets, a.duration, r["out"])
        if a.report_only or (a.reuse and manifest.get(r["key"], {}).get("cmd") == cmd and os.path.exists(r["out"])):
            continue
        jobs.append(dict(key=r["key"], cmd=cmd, out=r["out"], timeout=a.timeout))
    commit, dirty = git_state()
    info = dict(command="scripts/evaluate.py" + (f" {' '.join(argv if argv is not None else sys.argv[1:])}"
                                                  if (argv if argv is not None else sys.argv[1:]) else ""),
                commit=commit, dirty=dirty, nmdp=a.nmdp, out_dir=a.out_dir, duration=a.duration, sets=a.sets,
                variants=variants_of, jobs=a.jobs, sweep_wall=None)
    if jobs:
        log(f"{len(jobs)} runs, {a.jobs} at a time, into {a.out_dir}")
        info["sweep_wall"] = runs.execute(jobs, a.jobs, manifest, manifest_path, log)
        info["runs_made"] = len(jobs)
        info["summed"] = sum(manifest[j["key"]]["elapsed"] for j in jobs)
        log(f"the runs took {info['sweep_wall'] / 60:.1f} min")
    info["load"] = os.getloadavg()

    rows, data = measure_all(plan, manifest, {c["id"]: c for c in cases}, a)
    figs = {}
    from evaluation import figures
    for c in cases:
        path = figures.case_figure(c, [r for r in rows if r["case"] == c["id"] and r["variant"] == runs.DEFAULT], data,
                                   os.path.join(a.docs_dir, "figures"))
        if path:
            figs[c["id"]] = path
    os.makedirs(a.docs_dir, exist_ok=True)
    page = report.write(os.path.join(a.docs_dir, "RESULTS.md"), info, cases, skipped, rows, figs, a.methods, a.dts, a.dts[0])
    with open(os.path.join(a.out_dir, "rows.json"), "w") as f:
        json.dump(rows, f, indent=1, default=float)
    for ground, acc in report.acceptance(rows, cases, a.methods, a.dts[0]).items():
        if acc["rows"]:
            log(f"{ground}: {len(acc['passed'])} of {len(acc['rows'])} rows within 5 %")
    log(f"wrote {page}")


def measure_all(plan, manifest, case_by_id, a):
    """Every planned run measured (motion, stability) and compared with its reference."""
    rows, data = [], {}
    for r in plan:
        entry = manifest.get(r["key"])
        case = case_by_id[r["case"]]
        row = dict(case=r["case"], variant=r["variant"], method=r["method"], dt=r["dt"], key=r["key"],
                   rc=entry.get("rc") if entry else None, elapsed=entry.get("elapsed") if entry else None)
        d = None
        if os.path.exists(r["out"]):
            try:
                d = measure.load_run(r["out"])
                d["duration"] = a.duration
            except Exception as e:  # a broken file is a result too
                row.update(stable=False, why=f"unreadable ({e})")
        if d is not None:
            row.update(measure.motion(d, case["base"] == "planar"))
            if row["rc"] not in (0, None):
                row.update(stable=False, why="; ".join(x for x in (f"exit {row['rc']}", row["why"]) if x))
            data[r["key"]] = d
        elif "why" not in row:
            row.update(stable=False, why="no output file" + (f" (exit {row['rc']})" if row["rc"] is not None else " (not run)"))
        for k in ("x", "dxy", "yaw", "distance"):
            row.setdefault(k, float("nan"))
        rows.append(row)
    for row in rows:
        ref = next((x for x in rows if x["case"] == row["case"] and x["variant"] == row["variant"]
                    and x["method"] == row["method"] and x["dt"] == a.dts[0]), None)
        row["is_ref"] = ref is row
        row["rms"] = 0.0 if row["is_ref"] else measure.rms_deviation(data.get(row["key"]), data.get(ref["key"]) if ref else None)
        scale = abs(ref["distance"]) if ref else float("nan")
        row["rms_rel"] = row["rms"] / scale if scale > 0 else float("nan")
        row["dist_err"] = (row["distance"] - ref["distance"]) / scale if scale > 0 else float("nan")
        row["within"], row["reasons"] = measure.verdict(row, ref)
    return rows, data


if __name__ == "__main__":
    main()
