"""What is measured of a run and the verdict against its reference (the same case, variant and
method at the smallest dt). Pure functions of the trajectories, so that they can be tested on
made-up ones, and rows(), which applies them to every planned run."""
import json
import math
import os

import numpy as np

# Stable: the run completed, everything finite, the torso height within [Z_LOW, Z_HIGH] x its start
# height and the tilt from the vertical, arccos(cos roll cos pitch), below TILT_MAX at every step.
Z_LOW, Z_HIGH = 0.5, 1.5
TILT_MAX = 0.5  # rad, about 29 degrees
# Within 5 %: the acceptance of the step-size evaluation.
DISTANCE_TOLERANCE = 0.05  # relative to the reference's distance
RMS_TOLERANCE = 0.05       # RMS torso deviation relative to the reference's distance
YAW_MAX = 0.3              # rad, |final yaw|
# The straight walk on 3-D sand (plan.WALK_CASES): the largest |yaw| over the run, the largest
# lateral offset from the start line over the forward distance, and the forward distance against the
# same robot's planar-base run on the planar model of the same medium.
WALK_YAW_MAX = 0.1         # rad
WALK_LATERAL_MAX = 0.05    # of the forward distance
WALK_FORWARD_TOLERANCE = 0.10  # relative to the planar-base run's


def walk_verdict(row, planar):
    """(met, reasons) of a floating-base row on 3-D sand against its planar twin (rows of motion())."""
    reasons = []
    if not row["stable"]:
        reasons.append("not stable")
    if not row["yaw_max"] < WALK_YAW_MAX:
        reasons.append(f"|yaw| reached {row['yaw_max']:.3f} rad")
    forward = row["x"]
    if not (math.isfinite(forward) and forward > 0):
        reasons.append("it does not walk forward")
        return False, reasons
    if not row["y_max"] / forward < WALK_LATERAL_MAX:
        reasons.append(f"lateral drift {100 * row['y_max'] / forward:.1f} % of forward")
    if planar is None or not planar["stable"] or not planar["x"] > 0:
        reasons.append("no stable planar-base twin")
    else:
        err = (forward - planar["x"]) / planar["x"]
        if not abs(err) <= WALK_FORWARD_TOLERANCE:
            reasons.append(f"forward {100 * err:+.1f} % from the planar base's")
    return not reasons, reasons


def _text(value):
    if getattr(value, "shape", None) == () and hasattr(value, "item"):
        value = value.item()
    if isinstance(value, bytes):
        value = value.decode("utf-8", errors="replace")
    return str(value).rstrip("\0").strip()


def load_run(path):
    """time, torso position and rpy, status, the resolved scene and the per-step statistics of a run
    file (a killed run, still marked by its SWMR writer, opens as a SWMR reader)."""
    import h5py

    try:
        f = h5py.File(path, "r")
    except OSError:
        f = h5py.File(path, "r", swmr=True)
    with f:
        n = int(f["rows"][()]) if "rows" in f else int(f["steps"][()]) if "steps" in f else len(f["time"])
        d = dict(time=np.asarray(f["time"][:n], float), pos=np.asarray(f["base/position"][:n], float),
                 rpy=np.asarray(f["base/rpy"][:n], float), status=_text(f["status"][()]) if "status" in f else "unknown",
                 config=json.loads(_text(f.attrs["config"])) if "config" in f.attrs else {})
        for k in ("wall_time", "outer_iterations", "substeps"):
            d[k] = np.asarray(f["stats/" + k][:n], float) if "stats/" + k in f else np.full(n, np.nan)
    return d


def motion(d, planar):
    """Forward x, horizontal displacement |Δ(x, y)|, final yaw (unwrapped, from the start), the
    stability check and the cost of a trajectory d (time, pos, rpy, status, duration). The distance
    the verdict compares is |Δ(x, y)| on a floating base and x on a planar one."""
    t, pos, rpy = d["time"], d["pos"], d["rpy"]
    finite = np.all(np.isfinite(pos), axis=1) & np.all(np.isfinite(rpy), axis=1)
    n = len(t) if finite.all() else int(np.argmin(finite))
    why = []
    if d.get("status", "complete") != "complete":
        why.append(f"status '{d['status'][:80]}'")
    if n < len(t):
        why.append(f"NaN at t = {t[n]:.3f} s")
    if n == 0:
        return dict(stable=False, why="; ".join(why + ["no finite row"]), x=math.nan, dxy=math.nan, yaw=math.nan,
                    distance=math.nan, yaw_max=math.nan, y=math.nan, y_max=math.nan, t_end=0.0)
    z, h0 = pos[:n, 2], pos[0, 2]
    tilt = np.arccos(np.clip(np.cos(rpy[:n, 0]) * np.cos(rpy[:n, 1]), -1, 1))
    if t[n - 1] < d.get("duration", 0.0) - 1e-9:
        why.append(f"ended at t = {t[n - 1]:.3f} s")
    for bad, what in ((z < Z_LOW * h0, f"torso below {Z_LOW:g}x its start height"),
                      (z > Z_HIGH * h0, f"torso above {Z_HIGH:g}x its start height"),
                      (tilt > TILT_MAX, f"tilt over {TILT_MAX:g} rad")):
        if bad.any():
            why.append(f"{what} at t = {t[int(np.argmax(bad))]:.2f} s")
    x = float(pos[n - 1, 0] - pos[0, 0])
    dxy = float(math.hypot(x, pos[n - 1, 1] - pos[0, 1]))
    heading = np.unwrap(rpy[:n, 2]) - rpy[0, 2]
    yaw = float(heading[-1])
    lateral = pos[:n, 1] - pos[0, 1]
    wall = d.get("wall_time", np.full(len(t), np.nan))[1:n]
    wall = wall[np.isfinite(wall)]
    return dict(stable=not why, why="; ".join(why), x=x, dxy=dxy, yaw=yaw, distance=x if planar else dxy,
                yaw_max=float(np.max(np.abs(heading))), y=float(lateral[-1]), y_max=float(np.max(np.abs(lateral))),
                t_end=float(t[n - 1]), wall_per_s=float(wall.sum() / t[n - 1]) if len(wall) and t[n - 1] > 0 else math.nan,
                outer=float(np.nanmean(d["outer_iterations"][1:n])) if "outer_iterations" in d and n > 1 else math.nan)


def rms_deviation(run, ref):
    """RMS over the run's own times (up to the shorter run's end, finite rows only) of the 3-D torso
    distance from the reference, linearly interpolated."""
    if run is None or ref is None:
        return math.nan
    ok = np.all(np.isfinite(run["pos"]), axis=1)
    okr = np.all(np.isfinite(ref["pos"]), axis=1)
    if not ok.any() or not okr.any():
        return math.nan
    t, tr = run["time"], ref["time"][okr]
    sel = ok & (t <= min(t[ok].max(), tr.max()) + 1e-12)
    diff = np.stack([run["pos"][sel, i] - np.interp(t[sel], tr, ref["pos"][okr, i]) for i in range(3)], axis=1)
    return float(np.sqrt(np.mean(np.sum(diff ** 2, axis=1))))


def verdict(row, ref):
    """(within, reasons) for a row against its reference row (both from motion(), the row with 'rms'):
    within 5 % = both stable, the distance within DISTANCE_TOLERANCE of the reference's, the RMS
    deviation below RMS_TOLERANCE of it and |yaw| below YAW_MAX."""
    reasons = []
    if ref is None:
        return False, ["no reference run"]
    if not ref["stable"]:
        reasons.append("the reference is not stable")
    if not row["stable"]:
        reasons.append("not stable")
    scale = abs(ref["distance"])
    if not (math.isfinite(scale) and scale > 0):
        reasons.append("the reference does not move")
        return False, reasons
    err = abs(row["distance"] - ref["distance"]) / scale
    if not err <= DISTANCE_TOLERANCE:
        reasons.append(f"distance off by {100 * err:.1f} %")
    rel = row.get("rms", math.nan) / scale
    if not rel < RMS_TOLERANCE:
        reasons.append(f"RMS deviation {100 * rel:.1f} %")
    if not abs(row["yaw"]) < YAW_MAX:
        reasons.append(f"|yaw| {abs(row['yaw']):.2f} rad")
    return not reasons, reasons


def _row(run, entry, case, duration):
    """One run's row and its trajectory (None if there is no readable output)."""
    row = dict(case=run["case"], variant=run["variant"], method=run["method"], dt=run["dt"], key=run["key"],
               rc=entry.get("rc") if entry else None, elapsed=entry.get("elapsed") if entry else None)
    d = None
    if os.path.exists(run["out"]):
        try:
            d = load_run(run["out"])
            d["duration"] = duration
        except Exception as e:  # a broken file is a result too
            row.update(stable=False, why=f"unreadable ({e})")
    if d is not None:
        row.update(motion(d, case["base"] == "planar"))
        if row["rc"] not in (0, None):
            row.update(stable=False, why="; ".join(x for x in (f"exit {row['rc']}", row["why"]) if x))
    elif "why" not in row:
        row.update(stable=False, why="no output file" + (f" (exit {row['rc']})" if row["rc"] is not None else " (not run)"))
    for k in ("x", "dxy", "yaw", "distance", "yaw_max", "y", "y_max"):
        row.setdefault(k, math.nan)
    return row, d


def rows(runs, manifest, case_by_id, duration, reference_dt):
    """Every planned run (with its 'out' file) measured and compared with its reference, the run of
    the same case, variant and method at reference_dt. Returns (rows, {key: trajectory})."""
    out, data = [], {}
    for r in runs:
        row, d = _row(r, manifest.get(r["key"]), case_by_id[r["case"]], duration)
        if d is not None:
            data[r["key"]] = d
        out.append(row)
    for row in out:
        ref = next((x for x in out if x["case"] == row["case"] and x["variant"] == row["variant"]
                    and x["method"] == row["method"] and x["dt"] == reference_dt), None)
        row["is_ref"] = ref is row
        row["rms"] = 0.0 if row["is_ref"] else rms_deviation(data.get(row["key"]), data.get(ref["key"]) if ref else None)
        scale = abs(ref["distance"]) if ref else math.nan
        row["rms_rel"] = row["rms"] / scale if scale > 0 else math.nan
        row["dist_err"] = (row["distance"] - ref["distance"]) / scale if scale > 0 else math.nan
        row["within"], row["reasons"] = verdict(row, ref)
    return out, data
