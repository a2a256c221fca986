"""Sweeps of many `nmdp simulate` runs on a Dask cluster (`nmdp sweep`, docs/SWEEPS.md).

One concept per module: spec (the sweep file and its runs), check (the scene and keys checked by the
executable), task (one run, as a worker makes it), execute (the runs as Dask tasks), cluster (a
LocalCluster or an existing scheduler), progress (the progress bar), index (index.csv, index.h5),
main (the command). For scripts: run_jobs([Job(key, scene, sets, out), ...], binary, workers=N)
makes any list of runs on a LocalCluster (or scheduler=...) and returns their results.
"""
from .execute import Job, run_jobs  # noqa: F401
from .spec import Run, SweepError, load  # noqa: F401
