"""The Dask cluster a sweep runs on: a LocalCluster on this machine (one single-threaded worker
process per core by default: a run is a process of its own, so threads would only contend), or an
existing cluster's scheduler (`dask-scheduler` and `dask-worker`, on any number of machines)."""
import contextlib
import logging
import os
import signal
import tempfile
import threading


class ClusterError(RuntimeError):
    """The cluster could not be started or reached."""


def import_distributed():
    """The distributed package, or ClusterError saying how to install it."""
    try:
        import distributed
    except ImportError as e:
        raise ClusterError(f"the sweeps need Dask's distributed package for this Python ({e}); "
                           "Debian: apt install python3-distributed") from None
    return distributed


@contextlib.contextmanager
def _workers_ignore_ctrl_c():
    """SIGINT ignored while the LocalCluster starts its worker processes, which inherit that: a Ctrl-C
    then interrupts the sweep (which closes the cluster) and the runs (nmdp simulate handles its own
    signals), not every worker with a traceback of its own."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


@contextlib.contextmanager
def client(scheduler=None, workers=None, timeout=30):
    """A distributed.Client: to the scheduler at `scheduler` (tcp://HOST:PORT), or to a new
    LocalCluster of `workers` processes (default: the cores), closed on exit."""
    distributed = import_distributed()
    if scheduler:
        try:
            c = distributed.Client(scheduler, timeout=timeout)
        except (OSError, TimeoutError) as e:
            raise ClusterError(f"no Dask scheduler answers at {scheduler} ({e})") from None
        try:
            yield c
        finally:
            c.close()
        return
    n = workers or os.cpu_count() or 1
    # The workers' scratch folders in the temporary directory, not the current one; the scheduler's
    # HTTP server (it starts even without a dashboard) on a free port, not 8787, which another
    # cluster on this machine may hold (a warning on stderr); only errors logged.
    with tempfile.TemporaryDirectory(prefix="nmdp-sweep-") as scratch:
        with _workers_ignore_ctrl_c():
            cluster = distributed.LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                               dashboard_address=":0", local_directory=scratch,
                                               silence_logs=logging.ERROR)
        try:
            with distributed.Client(cluster) as c:
                yield c
        finally:
            cluster.close()
