"""Checking a sweep's scene and override keys with the nmdp executable itself before anything runs,
so a misspelt key stops the sweep with the executable's own message instead of failing every run.

The first run is made for one step (its overrides, then duration 1e-9 s: scheduledSteps makes that
one step), which reads the scene, the robot and the contact model and builds the simulation; so is
the first run that sets a key no earlier check set. A key's other values are checked by their runs
(a bad one is that run's "failed: ..." in the index): checking every run would double the sweep.
"""
import os
import subprocess
import tempfile

from .spec import SweepError

ONE_STEP = "duration=1e-9"
PREFIX = "nmdp simulate: error: "


def runs_to_check(runs):
    """The first run, then each run setting a key no run before it in this list sets."""
    chosen, covered = [], set()
    for r in runs:
        if not chosen or set(r.overrides) - covered:
            chosen.append(r)
            covered |= set(r.overrides)
    return chosen


def check(binary, sweep_path, runs, describe):
    """Runs each of runs_to_check(runs) for one step; SweepError "<sweep file>: <describe(run)>:
    <the executable's message>" for one it rejects as bad input (exit 1). A run that starts but fails
    its step (exit 4) is not bad input: it runs, and fails, with the others."""
    with tempfile.TemporaryDirectory(prefix="nmdp-sweep-check-") as folder:
        out = os.path.join(folder, "check.h5")
        for run in runs_to_check(runs):
            cmd = [binary, "simulate", run.scene]
            for s in run.sets() + [ONE_STEP]:
                cmd += ["--set", s]
            cmd += ["--out", out, "--quiet"]
            try:
                p = subprocess.run(cmd, stdin=subprocess.DEVNULL, capture_output=True, text=True, errors="replace")
            except OSError as e:
                raise SweepError(f"{binary}: {e.strerror}") from None
            if p.returncode == 1:
                lines = [ln for ln in p.stderr.splitlines() if ln.strip()]
                why = lines[-1] if lines else "exit 1"
                why = why[len(PREFIX):] if why.startswith(PREFIX) else why
                raise SweepError(f"{sweep_path}: {describe(run)}: {why}")
            if p.returncode not in (0, 4):
                raise SweepError(f"{sweep_path}: {describe(run)}: nmdp simulate ended with exit {p.returncode}: "
                                 f"{p.stderr.strip()[-300:]}")
