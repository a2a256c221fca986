"""One run of a sweep, as a Dask worker executes it: `nmdp simulate` as a subprocess writing a
temporary file that is renamed to the run's file only when the run completed.

This module uses the standard library only: the client ships it to the workers by value
(cloudpickle), so a plain `dask-worker` needs neither nmdp's Python package nor its compiled part,
only the nmdp executable and the files at the same paths (a shared file system).
"""
import ctypes
import os
import signal
import subprocess
import time
import uuid

_PR_SET_PDEATHSIG = 1  # linux/prctl.h
_SIGKILL = int(signal.SIGKILL)


def _libc_prctl():
    try:
        return ctypes.CDLL(None, use_errno=True).prctl
    except (OSError, AttributeError):
        return None


def _die_with_parent(parent_pid, prctl):
    """preexec_fn: the child gets SIGKILL when the worker thread that started it dies (a killed
    worker must not leave its run going on), and ends at once if the worker died before this ran.
    prctl is looked up before the fork, so the child only calls it."""
    def set_death_signal():
        if prctl is not None:
            prctl(_PR_SET_PDEATHSIG, _SIGKILL, 0, 0, 0)
        if os.getppid() != parent_pid:
            os._exit(1)
    return set_death_signal


def _last_line(text):
    lines = [ln.strip() for ln in text.splitlines() if ln.strip()]
    return lines[-1] if lines else ""


def _remove(path):
    try:
        os.remove(path)
    except FileNotFoundError:
        pass


def run_one(binary, scene, sets, out, timeout=None):
    """Runs `binary simulate scene --set ... --out <out>.part-<uuid> --quiet` and renames the file to
    `out` when it exits 0 (os.replace: atomic, a reader never sees a half-written run). A failed
    run's file is deleted. Returns dict(out, cmd, status: "complete" or "failed: <last stderr line>",
    returncode (an int, or "timeout"), wall: seconds, stderr: its last 500 characters)."""
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    part = f"{out}.part-{uuid.uuid4().hex[:12]}"
    cmd = [binary, "simulate", scene]
    for s in sets:
        cmd += ["--set", s]
    cmd += ["--out", part, "--quiet"]
    start = time.monotonic()
    try:
        p = subprocess.run(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                           errors="replace", timeout=timeout, preexec_fn=_die_with_parent(os.getpid(), _libc_prctl()))
        rc, err = p.returncode, p.stderr.strip()
    except subprocess.TimeoutExpired:
        rc, err = "timeout", f"killed after {timeout:g} s"
    except OSError as e:  # the binary is not on this worker, or not executable
        rc, err = "not started", f"{binary}: {e.strerror}"
    wall = time.monotonic() - start
    if rc == 0:
        os.replace(part, out)
        status = "complete"
    else:
        _remove(part)
        if isinstance(rc, int) and rc < 0:
            err = (err + "\n" if err else "") + f"killed by signal {-rc}"
        why = _last_line(err) or f"exit {rc}"
        # "...; <part> keeps the N completed steps": that file is deleted, the reason is what stays true.
        status = "failed: " + why.split(f"; {part} ")[0]
    return dict(out=out, cmd=cmd, status=status, returncode=rc, wall=wall, stderr=err[-500:])
