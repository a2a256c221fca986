"""The step-size evaluation with the scene defaults: every case at dt = 1, 5, 10, 20, 50 ms with the
default method and its PBD twin, each against the same method's 1 ms run; writes docs/RESULTS.md and
docs/figures/steps_*.png, every claim computed from the runs.

Usage:
    scripts/evaluate.py                         # the evaluation: 10 s runs, page in docs/
    scripts/evaluate.py --duration 0.2          # a smoke run: page and runs in build/evaluation-short/
    scripts/evaluate.py --set integrator.order=2 --set integrator.accuracy=1e-3   # settings for every run
    scripts/evaluate.py --variant "kd 3" controller.kd=3   # extra labelled rows (their own 1 ms reference)
    scripts/evaluate.py --no-variants           # only the defaults' rows, not the cases' built-in variants

Cases: one scene file each in models/scenes/evaluation/ (the project's quadruped, A1 and Solo-12
trotting on flat ground with a floating base; RoboSimian walking with the paper's planar base on
rigid ground and on the published sand model; the quadruped's planar trot on the project's sand
model), holding only the robot and the keys that define the case. Every case carries labelled
variants (scripts/evaluation/plan.py): the paper's method (K = full-body, no error control), no
error control, order 2 with and without error control, and for some the former evaluation's gains,
swing profile and start ramp (A1: kd = 3): extra rows against their own 1 ms run, never part of the
verdict. Robots in ../shared are read in place, and a case whose files are absent is skipped with a
message.

The package: plan (cases, variants, runs and commands), run (the runs through nmdp's sweep library on
a LocalCluster of --jobs workers or a Dask cluster's --scheduler, the manifest),
metrics (what is measured of a run, the verdict), figures, report (the page).

Needs Debian's python3 (h5py, numpy, matplotlib, python3-distributed) and a built nmdp (default
build/nmdp, with its Python package beside it in build/python). Results go to
--out-dir (default build/evaluation, or build/evaluation-short below 10 s): the HDF5 runs,
manifest.json and rows.json. Never commit them.
"""
import argparse
import json
import os
import sys

from . import metrics, plan, report, run

PROG = "evaluate.py"


def parse_args(argv):
    ap = argparse.ArgumentParser(prog=PROG, description=__doc__.split("\n\n")[0], epilog=__doc__.split("\n\n", 1)[1],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--duration", type=float, default=10.0, help="simulated seconds per run (default 10; less is a smoke run)")
    ap.add_argument("--set", dest="sets", action="append", default=[], metavar="KEY=VALUE",
                    help="passed to every run as nmdp simulate --set (repeatable), e.g. integrator.order=2")
    ap.add_argument("--variant", nargs="+", action="append", default=[], metavar=("LABEL", "KEY=VALUE"),
                    help="extra labelled rows for every case: LABEL then --set settings")
    ap.add_argument("--no-variants", dest="variants", action="store_false",
                    help="leave out each case's built-in labelled variants (the former evaluation's tuning)")
    ap.add_argument("--cases", default=None, help="comma-separated case ids (default: all)")
    ap.add_argument("--methods", default=",".join(plan.METHODS), help="comma-separated methods (default ne-pgm,pbd-pgm)")
    ap.add_argument("--dts", default=",".join(f"{dt:g}" for dt in plan.DTS),
                    help="comma-separated dt in s; the smallest is the reference (default 0.001,0.005,0.01,0.02,0.05)")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 2,
                    help="runs at a time: the LocalCluster's worker processes (default: the number of cores)")
    ap.add_argument("--scheduler", default=None, metavar="tcp://HOST:PORT",
                    help="run on this Dask cluster instead (docs/SWEEPS.md); its workers see these paths")
    ap.add_argument("--out-dir", default=None, help="results folder (default build/evaluation, build/evaluation-short below 10 s)")
    ap.add_argument("--docs-dir", default=None, help="where RESULTS.md and figures/ go (default docs/; below 10 s the results folder)")
    ap.add_argument("--nmdp", default=os.path.join(plan.ROOT, "build", "nmdp"), help="the nmdp binary (default build/nmdp)")
    ap.add_argument("--reuse", action="store_true", help="keep runs already made with the same command")
    ap.add_argument("--report-only", action="store_true", help="run nothing; read --out-dir and write the page")
    ap.add_argument("--timeout", type=float, default=1800, help="seconds before a run is killed (default 1800)")
    a = ap.parse_args(argv)
    if a.duration <= 0:
        ap.error("--duration must be positive")
    if a.jobs < 1:
        ap.error("--jobs must be at least 1")
    for v in a.variant:
        if len(v) < 2 or any("=" not in s for s in v[1:]):
            ap.error(f"--variant {' '.join(v)}: give a label and at least one KEY=VALUE")
    if any("=" not in s for s in a.sets):
        ap.error("--set takes KEY=VALUE")
    short = a.duration < 10
    a.out_dir = os.path.abspath(a.out_dir or os.path.join(plan.ROOT, "build", "evaluation-short" if short else "evaluation"))
    a.docs_dir = os.path.abspath(a.docs_dir or (a.out_dir if short else os.path.join(plan.ROOT, "docs")))
    a.nmdp = os.path.abspath(a.nmdp)
    a.methods = a.methods.split(",")
    a.dts = sorted(float(x) for x in a.dts.split(","))
    return a


def _log(msg):
    print(f"{PROG}: {msg}", file=sys.stderr)


def choose_cases(a):
    """The cases asked for that can run here, and why the others were skipped."""
    all_cases = plan.all_cases()
    ids = [c["id"] for c in all_cases]
    chosen = set(a.cases.split(",")) if a.cases else None
    if chosen and chosen - set(ids):
        sys.exit(f"{PROG}: error: unknown case(s) {', '.join(sorted(chosen - set(ids)))}; the cases are {', '.join(ids)}")
    cases, skipped = [], []
    for c in all_cases:
        if chosen and c["id"] not in chosen:
            continue
        why = plan.missing(c)
        if why:
            _log(f"skipping {c['id']}: {why}")
            skipped.append(f"{c['id']}: {why}")
            continue
        plan.check_defaults(c)
        cases.append(c)
    return cases, skipped


def make_runs(a, cases, variants_of, info):
    """Plans every run, makes those not already made (with --reuse) and returns (runs, manifest)."""
    runs = plan.runs(cases, variants_of, a.methods, a.dts)
    os.makedirs(a.out_dir, exist_ok=True)
    manifest_path = os.path.join(a.out_dir, "manifest.json")
    manifest = {}
    if os.path.exists(manifest_path) and (a.reuse or a.report_only):
        with open(manifest_path) as f:
            manifest = json.load(f)
    path_of = {c["id"]: c["path"] for c in cases}
    jobs = []
    for r in runs:
        r["out"] = os.path.join(a.out_dir, "runs", r["key"] + ".h5")
        cmd = plan.command(a.nmdp, path_of[r["case"]], r, a.sets, a.duration, r["out"])
        if a.report_only or (a.reuse and manifest.get(r["key"], {}).get("cmd") == cmd and os.path.exists(r["out"])):
            continue
        jobs.append(dict(key=r["key"], cmd=cmd, out=r["out"], timeout=a.timeout))
    if jobs:
        _log(f"{len(jobs)} runs, " + (f"on {a.scheduler}" if a.scheduler else f"{a.jobs} at a time") + f", into {a.out_dir}")
        info["sweep_wall"] = run.execute(jobs, a.jobs, manifest, manifest_path, _log, a.scheduler)
        info["runs_made"] = len(jobs)
        info["summed"] = sum(manifest[j["key"]]["elapsed"] for j in jobs)
        _log(f"the runs took {info['sweep_wall'] / 60:.1f} min")
    return runs, manifest


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    a = parse_args(argv)
    if not a.report_only and not os.access(a.nmdp, os.X_OK):
        sys.exit(f"{PROG}: error: {a.nmdp} is not an executable (build it with scripts/build.sh, or pass --nmdp)")
    cases, skipped = choose_cases(a)

    def variants_of(case):
        v = dict(case["variants"]) if a.variants else {}
        v.update({x[0]: x[1:] for x in a.variant})
        return v

    commit, dirty = run.git_state()
    info = dict(command="scripts/evaluate.py" + "".join(f" {x}" for x in argv), commit=commit, dirty=dirty,
                nmdp=a.nmdp, out_dir=a.out_dir, duration=a.duration, sets=a.sets, variants=variants_of, jobs=a.jobs,
                sweep_wall=None)
    runs, manifest = make_runs(a, cases, variants_of, info)
    info["load"] = os.getloadavg()
    rows, data = metrics.rows(runs, manifest, {c["id"]: c for c in cases}, a.duration, a.dts[0])
    from . import figures  # matplotlib only once there is something to draw
    figs = {}
    for c in cases:
        path = figures.case_figure(c, [r for r in rows if r["case"] == c["id"] and r["variant"] == plan.DEFAULT], data,
                                   os.path.join(a.docs_dir, "figures"))
        if path:
            figs[c["id"]] = path
    os.makedirs(a.docs_dir, exist_ok=True)
    page = report.write(os.path.join(a.docs_dir, "RESULTS.md"), info, cases, skipped, rows, figs, a.methods, a.dts, a.dts[0])
    with open(os.path.join(a.out_dir, "rows.json"), "w") as f:
        json.dump(rows, f, indent=1, default=float)
    for ground, acc in report.acceptance(rows, cases, a.methods, a.dts[0]).items():
        if acc["rows"]:
            _log(f"{ground}: {len(acc['passed'])} of {len(acc['rows'])} rows {report.WITHIN}")
    _log(f"wrote {page}")
