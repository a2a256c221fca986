"""`nmdp sweep SWEEP.json --out DIR [--scheduler tcp://HOST:PORT] [--workers N] [--quiet]`: every run
of the sweep file as one Dask task writing DIR/runs/<id>.h5, then DIR/index.csv and DIR/index.h5.

Exit status: 0 every run completed; 4 some failed (the index says which and why); 1 bad input
(nothing ran); 130 interrupted (the runs completed so far are kept; a re-run continues).
"""
import argparse
import os
import sys

from . import check, cluster, execute, index, spec
from .progress import Progress

PROG = "nmdp sweep"


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # bad options are bad input: exit 1, as nmdp's other commands
        raise spec.SweepError(f"{message} (see nmdp sweep --help)")


def parse_args(argv):
    ap = _Parser(prog=PROG, description=__doc__.split("\n\n")[0])
    ap.add_argument("sweep", metavar="SWEEP.json")
    ap.add_argument("--out", required=True, metavar="DIR", help="the results folder (runs/, index.csv, index.h5)")
    ap.add_argument("--scheduler", metavar="tcp://HOST:PORT", help="an existing Dask scheduler (default: a LocalCluster)")
    ap.add_argument("--workers", type=int, metavar="N", help="LocalCluster worker processes (default: the cores)")
    ap.add_argument("--quiet", "-q", action="store_true", help="no progress bar and no summary")
    a = ap.parse_args(argv)
    if a.workers is not None and a.workers < 1:
        raise spec.SweepError(f"--workers {a.workers}: at least 1")
    if a.workers is not None and a.scheduler:
        raise spec.SweepError("--workers sizes a LocalCluster; with --scheduler the cluster has its own workers")
    return a


def find_binary():
    """The nmdp executable: NMDP_BINARY (set by `nmdp sweep`), else the one this package was built with."""
    binary = os.environ.get("NMDP_BINARY")
    if not binary:
        try:
            from .. import _build
            binary = _build.NMDP_BINARY
        except ImportError:
            raise spec.SweepError("NMDP_BINARY is not set and this package has no _build.py: "
                                  "run the sweep as `nmdp sweep`") from None
    if not os.access(binary, os.X_OK):
        raise spec.SweepError(f"{binary}: not an executable (NMDP_BINARY)")
    return os.path.abspath(binary)


def describe(sweep):
    """describe(run): where a run comes from and what it sets, for messages."""
    def text(run):
        return f"run {run.id} ({' '.join(f'{k}={spec.canonical(v)}' for k, v in run.overrides.items()) or 'no overrides'})"
    return text


def _log(a, message):
    if not a.quiet:
        print(f"{PROG}: {message}", file=sys.stderr, flush=True)


def plan(a, sweep):
    """The runs still to make (those without a complete DIR/runs/<id>.h5), saying how many are done."""
    runs_dir = os.path.join(a.out, "runs")
    try:
        os.makedirs(runs_dir, exist_ok=True)
    except OSError as e:
        raise spec.SweepError(f"--out {a.out}: {e.strerror}") from None
    todo = [r for r in sweep.runs if not index.is_complete(os.path.join(runs_dir, r.id + ".h5"))]
    _log(a, f"{len(sweep.runs) - len(todo)} runs already complete, {len(todo)} to run")
    return todo


def run(a, binary, sweep, todo):
    """Makes the runs in `todo` with a progress bar; returns {id: result}."""
    jobs = [execute.Job(key=r.id, scene=r.scene, sets=r.sets(), out=os.path.join(a.out, "runs", r.id + ".h5"))
            for r in todo]
    if not jobs:
        return {}
    if not a.scheduler:
        _log(a, f"starting a LocalCluster of {a.workers or os.cpu_count() or 1} workers")
    bar = Progress(len(jobs), quiet=a.quiet)
    try:
        return execute.run_jobs(jobs, binary, workers=a.workers, scheduler=a.scheduler,
                                on_result=lambda job, result: bar.update(result["status"] != "complete"))
    finally:
        bar.finish()


def summarize(a, sweep, table):
    failed = [row for row in table if row["status"] != "complete"]
    if a.quiet:
        return
    by_id = {r.id: r for r in sweep.runs}
    for row in failed[:10]:
        print(f"{PROG}: {describe(sweep)(by_id[row['id']])}: {row['status']}", file=sys.stderr)
    if len(failed) > 10:
        print(f"{PROG}: ... and {len(failed) - 10} more failed runs (see the index)", file=sys.stderr)
    print(f"{os.path.join(a.out, 'index.csv')}: {len(table)} runs, {len(table) - len(failed)} complete, "
          f"{len(failed)} failed")


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    a = None
    try:
        a = parse_args(argv)
        a.out = os.path.abspath(a.out)
        binary = find_binary()
        sweep = spec.load(a.sweep)
        cluster.import_distributed()
        check.check(binary, a.sweep, sweep.runs, describe(sweep))
        todo = plan(a, sweep)
        results = run(a, binary, sweep, todo)
        table = index.write(a.out, sweep.runs, results)
    except (spec.SweepError, cluster.ClusterError) as e:
        print(f"{PROG}: error: {e}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        kept = f" in {a.out}/runs" if a else ""
        print(f"\n{PROG}: interrupted; the runs completed so far are kept{kept}, and a re-run makes the others",
              file=sys.stderr)
        return 130
    summarize(a, sweep, table)
    return 0 if all(row["status"] == "complete" for row in table) else 4
