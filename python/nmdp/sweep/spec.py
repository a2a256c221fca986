"""The sweep file and its expansion into runs.

A sweep file is JSON: {"scene": path (relative to the sweep file), "base": {key: value} (overrides
of every run), "grid": {key: [values]} (every combination, in the keys' order as written), "runs":
[{key: value}, ...] (listed runs, after the grid's)}; keys as `nmdp simulate --set` takes them. Each
run is the base with its own overrides on top. Anything wrong gives one SweepError naming the file
and the key, before anything runs.
"""
import hashlib
import itertools
import json
import math
import os
from dataclasses import dataclass, field

TOP_LEVEL_KEYS = ("scene", "base", "grid", "runs")
# A grid that expands beyond this is a mistake (a million runs of even 0.1 s is days of CPU), not a sweep.
MAX_RUNS = 100_000
# A sweep file is a few kilobytes; this only keeps a wrong file (a trajectory, a log) from being read whole.
MAX_FILE_BYTES = 64 << 20


class SweepError(ValueError):
    """Bad input in a sweep: the message names the file and the key."""


@dataclass
class Run:
    """One run: the scene (absolute path), its overrides in the order they are applied (the base's
    first, then the run's own), and its stable id."""
    scene: str
    overrides: dict
    id: str = field(default="")

    def __post_init__(self):
        if not self.id:
            self.id = run_id(self.scene, self.overrides)

    def sets(self):
        """The overrides as `--set` arguments, KEY=JSON (a string value quoted, so "1" stays a string)."""
        return [f"{k}={json.dumps(v, separators=(',', ':'))}" for k, v in self.overrides.items()]


@dataclass
class Sweep:
    path: str    # the sweep file, as given
    scene: str   # absolute
    runs: list   # of Run, grid combinations first, then the listed runs

    def keys(self):
        """Every override key any run sets, in the order they first appear."""
        return list(dict.fromkeys(k for r in self.runs for k in r.overrides))


def canonical(value):
    """JSON with sorted keys and no spaces: equal overrides give equal text, whatever their order."""
    return json.dumps(value, sort_keys=True, separators=(",", ":"), allow_nan=False)


def run_id(scene, overrides):
    """A short hash of the scene's path and the run's overrides: the same run in a re-run, or in
    another sweep file into the same folder, finds its file; 12 hex digits make a collision among
    even a million runs about one in a million."""
    text = os.path.abspath(scene) + "\n" + canonical(overrides)
    return hashlib.sha256(text.encode()).hexdigest()[:12]


def _reject_duplicates(pairs):
    keys = [k for k, _ in pairs]
    for k in keys:
        if keys.count(k) > 1:
            raise SweepError(f"key '{k}' appears twice in one object")
    return dict(pairs)


def _reject_constant(name):
    raise SweepError(f"{name} is not JSON (a number must be finite)")


def _finite_float(text):
    value = float(text)
    if not math.isfinite(value):
        raise SweepError(f"{text} is out of range (a number must be finite)")
    return value


def read_json(path):
    """The file's JSON; SweepError "PATH: why" for a missing, oversized or malformed file."""
    try:
        size = os.stat(path).st_size
        if not os.path.isfile(path):
            raise SweepError(f"{path}: not a regular file")
        if size > MAX_FILE_BYTES:
            raise SweepError(f"{path}: {size} bytes, more than a sweep file's {MAX_FILE_BYTES} bytes")
        with open(path, encoding="utf-8") as f:
            return json.load(f, object_pairs_hook=_reject_duplicates, parse_constant=_reject_constant,
                             parse_float=_finite_float)
    except SweepError as e:
        raise SweepError(str(e) if str(e).startswith(f"{path}:") else f"{path}: {e}") from None
    except OSError as e:
        raise SweepError(f"{path}: {e.strerror}") from None
    except (UnicodeDecodeError, json.JSONDecodeError, RecursionError) as e:
        raise SweepError(f"{path}: not valid JSON ({e})") from None


def _check_key(path, where, key):
    if not key or key != key.strip() or "=" in key or key.startswith("-"):
        raise SweepError(f"{path}: {where}: '{key}' is not a scene key (as --set takes it, e.g. integrator.dt)")


def _check_overrides(path, where, obj):
    """An object of key: value, each key as --set takes it."""
    if not isinstance(obj, dict):
        raise SweepError(f"{path}: {where}: an object of key: value expected, got {canonical(obj)[:80]}")
    for k in obj:
        _check_key(path, where, k)
    return obj


def _merge(base, own):
    """The base's overrides the run does not set, then the run's: a run's key applies after the
    base's, so a run may set a key inside an object the base replaces."""
    merged = {k: v for k, v in base.items() if k not in own}
    merged.update(own)
    return merged


def _grid_runs(path, scene, base, grid):
    if not isinstance(grid, dict):
        raise SweepError(f"{path}: grid: an object of key: [values] expected")
    count = 1
    for k, values in grid.items():
        _check_key(path, "grid", k)
        if not isinstance(values, list) or not values:
            raise SweepError(f"{path}: grid.{k}: a non-empty list of values expected")
        count *= len(values)
        if count > MAX_RUNS:
            raise SweepError(f"{path}: grid: more than {MAX_RUNS} combinations")
    if not grid:
        return []
    keys = list(grid)
    return [Run(scene, _merge(base, dict(zip(keys, combo)))) for combo in itertools.product(*grid.values())]


def _listed_runs(path, scene, base, runs):
    if not isinstance(runs, list):
        raise SweepError(f"{path}: runs: a list of objects expected")
    if len(runs) > MAX_RUNS:
        raise SweepError(f"{path}: runs: more than {MAX_RUNS} runs")
    return [Run(scene, _merge(base, _check_overrides(path, f"runs[{i}]", r))) for i, r in enumerate(runs)]


def _describe(i, grid_count):
    """Where run i of the expansion comes from: a grid combination (1-based, the last key varying
    fastest) or runs[j]."""
    return f"grid combination {i + 1}" if i < grid_count else f"runs[{i - grid_count}]"


def load(path):
    """The sweep in the file at `path`: its scene (must exist) and every run, checked for unknown
    keys, malformed grids and runs, no runs at all and duplicate runs (SweepError)."""
    spec = read_json(path)
    if not isinstance(spec, dict):
        raise SweepError(f"{path}: an object with scene, base, grid and runs expected")
    for k in spec:
        if k not in TOP_LEVEL_KEYS:
            raise SweepError(f"{path}: unknown key '{k}' (a sweep file has {', '.join(TOP_LEVEL_KEYS)})")
    scene = spec.get("scene")
    if not isinstance(scene, str) or not scene:
        raise SweepError(f"{path}: scene: the scene file's path expected (relative to the sweep file)")
    scene = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(path)), scene))
    if not os.path.isfile(scene):
        raise SweepError(f"{path}: scene: {scene} is not a file")
    base = _check_overrides(path, "base", spec.get("base", {}))
    grid = _grid_runs(path, scene, base, spec.get("grid", {}))
    runs = grid + _listed_runs(path, scene, base, spec.get("runs", []))
    if not runs:
        raise SweepError(f"{path}: no runs: give a grid or runs (an empty run [{{}}] is the scene as it is)")
    if len(runs) > MAX_RUNS:
        raise SweepError(f"{path}: more than {MAX_RUNS} runs")
    seen = {}
    for i, r in enumerate(runs):
        if r.id in seen:
            raise SweepError(f"{path}: {_describe(i, len(grid))} is the same run as {_describe(seen[r.id], len(grid))}: "
                             f"{canonical(r.overrides)}")
        seen[r.id] = i
    return Sweep(path=path, scene=scene, runs=runs)
