"""Running many `nmdp simulate` runs as Dask tasks, one task per run, and collecting their results
as they finish. A task whose worker dies is rescheduled by the scheduler on another worker (its
child process dies with the worker, see task.py); one that raises is retried.
"""
import os
import uuid
from dataclasses import dataclass

from . import cluster, task

# Retries of a task that raised (e.g. a worker whose disk filled); a run that fails (exit non-zero)
# returns its status instead of raising, since running it again would fail the same way.
RETRIES = 2


@dataclass
class Job:
    """One run to make: the scene, its `--set` arguments (KEY=VALUE, applied in order), the final
    output file, and a label the results are keyed by (the run's id, or any unique name)."""
    key: str
    scene: str
    sets: list
    out: str


def _ship_task_by_value():
    """Workers receive task.run_one's code with each task, so they need not import nmdp (nor its
    compiled part) to run one."""
    import cloudpickle
    if hasattr(cloudpickle, "register_pickle_by_value"):
        cloudpickle.register_pickle_by_value(task)


def _failed(job, why):
    return dict(out=job.out, cmd=None, status=f"failed: {why}", returncode=None, wall=0.0, stderr=why)


def submit_and_collect(dask_client, jobs, binary, timeout=None, on_result=None):
    """Submits every job to the cluster (in the order given, which is the order they tend to start)
    and returns {job.key: result} (task.run_one's dict). on_result(job, result) is called as each
    finishes, in the order they finish."""
    distributed = cluster.import_distributed()
    _ship_task_by_value()
    tag = uuid.uuid4().hex[:8]
    futures = {}
    for i, job in enumerate(jobs):
        f = dask_client.submit(task.run_one, binary, job.scene, list(job.sets), job.out, timeout,
                               key=f"nmdp-run-{tag}-{i}", pure=False, retries=RETRIES)
        futures[f] = job
    results = {}
    try:
        for f in distributed.as_completed(list(futures)):
            job = futures[f]
            try:
                result = f.result()
            except Exception as e:  # noqa: BLE001 (the scheduler gave up: e.g. KilledWorker after repeated deaths)
                result = _failed(job, f"{type(e).__name__}: {e}".splitlines()[0])
            results[job.key] = result
            if on_result:
                on_result(job, result)
    finally:
        for f in futures:
            if not f.done():
                f.cancel()
    _remove_orphans(jobs)
    return results


def _remove_orphans(jobs):
    """Deletes the temporary files of runs whose worker was killed mid-run (its retry, elsewhere,
    wrote another): every task has ended, so none is being written."""
    names = {}
    for job in jobs:
        folder, name = os.path.split(os.path.abspath(job.out))
        names.setdefault(folder, set()).add(name)
    for folder, finals in names.items():
        try:
            entries = os.listdir(folder)
        except OSError:
            continue
        for entry in entries:
            if ".part-" in entry and entry.rsplit(".part-", 1)[0] in finals:
                try:
                    os.remove(os.path.join(folder, entry))
                except OSError:
                    pass


def run_jobs(jobs, binary, workers=None, scheduler=None, timeout=None, on_result=None):
    """The jobs on a new LocalCluster of `workers` processes, or on the cluster at `scheduler`;
    returns {job.key: result}."""
    if not jobs:
        return {}
    with cluster.client(scheduler, workers) as c:
        return submit_and_collect(c, jobs, binary, timeout, on_result)
