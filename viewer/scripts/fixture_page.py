#!/usr/bin/python3
"""Development stand-in for `nmdp view`: writes a page (payload.md's format, version 1) from run files
of the current layout (no link poses or foot points: the trunk is a box at the base pose).
Usage: fixture_page.py OUT.html RUN.h5 [RUN2.h5 ...]"""
import base64, json, math, os, sys
import h5py
import numpy as np

def arr(a, dtype):
    a = np.ascontiguousarray(a, dtype=dtype)
    return {"dtype": dtype, "shape": list(a.shape), "b64": base64.b64encode(a.astype("<" + a.dtype.str[1:]).tobytes()).decode()}

def rpy_to_quat(rpy):
    r, p, y = rpy[:, 0] / 2, rpy[:, 1] / 2, rpy[:, 2] / 2
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    return np.stack([sr*cp*cy - cr*sp*sy, cr*sp*cy + sr*cp*sy, cr*cp*sy - sr*sp*cy, cr*cp*cy + sr*sp*sy], axis=1)

def run_of(path):
    f = h5py.File(path, "r", swmr=True)
    n = int(f["steps"][()])
    status = f["status"][()].decode().rstrip("\0")
    time = f["time"][:n]
    pos = f["base/position"][:n]
    quat = rpy_to_quat(f["base/rpy"][:n])
    names = [s.decode() for s in f["joint_names"][:]]
    wrench = f["contacts/wrench"][:n]
    cnames = [s.decode() for s in f["contacts/names"][:]]
    heading = np.array([math.cos(f["base/rpy"][0, 2]), math.sin(f["base/rpy"][0, 2])])
    warnings = [f"{os.path.basename(path)} has no /model/urdf: the trunk is drawn as a box"]
    if status == "running":
        warnings.append(f"{os.path.basename(path)} was cut short (status 'running'): {n} committed rows")
    return {
        "label": f"{os.path.basename(path)}: {f.attrs.get('method', '?')}, dt = {float(f.attrs.get('dt', 0))*1000:g} ms",
        "file": os.path.abspath(path), "status": status, "warnings": warnings, "frames": n,
        "time": arr(time, "float64"),
        "links": [{"name": "trunk", "visuals": [{"type": "box", "size": [0.4, 0.2, 0.1], "origin": [0, 0, 0, 0, 0, 0, 1], "color": None, "source": "inertia"}]}],
        "link_poses": None,
        "base": {"position": arr(pos, "float32"), "quaternion": arr(quat, "float32")},
        "contacts": {"names": cnames, "points": None, "forces": arr(wrench[:, :, 3:6], "float32"), "normal_force": arr(wrench[:, :, 5], "float32")},
        "joints": {"names": names, "q": arr(f["q"][:n], "float32")},
        "series": {"torso_height": arr(pos[:, 2], "float32"), "forward_distance": arr((pos[:, :2] - pos[0, :2]) @ heading, "float32")},
    }, pos

def main():
    out, paths = sys.argv[1], sys.argv[2:]
    runs, positions = zip(*(run_of(p) for p in paths))
    allp = np.concatenate(positions)
    lo, hi = allp[:, :2].min(0) - 1, allp[:, :2].max(0) + 1
    spacing = 0.02
    nx, ny = [int(min(256, math.ceil((hi[i] - lo[i]) / spacing) + 1)) for i in (0, 1)]
    sx, sy = (hi[0] - lo[0]) / (nx - 1), (hi[1] - lo[1]) / (ny - 1)
    xs, ys = lo[0] + sx * np.arange(nx), lo[1] + sy * np.arange(ny)
    heights = np.zeros((ny, nx))
    material = ((np.abs(ys)[:, None] < 0.5) & (xs[None, :] > 0.5)).astype(np.uint8)  # a sand patch
    payload = {
        "format": "nmdp-view", "version": 1, "generator": "fixture_page.py", "warnings": [],
        "terrain": {"kind": "grid", "description": "plane z = 0", "origin": [float(lo[0]), float(lo[1])], "spacing": [sx, sy], "size": [nx, ny],
                    "heights": arr(heights, "float32"), "material": arr(material, "uint8"),
                    "materials": [{"name": "rigid", "color": [0.6, 0.6, 0.58]}, {"name": "sand", "color": [0.86, 0.74, 0.5]}]},
        "runs": list(runs),
    }
    bundle = open(os.path.join(os.path.dirname(__file__), "..", "dist", "nmdp-view.js"), encoding="utf-8").read()
    data = json.dumps(payload).replace("<", "\\u003c")
    with open(out, "w", encoding="utf-8") as f:
        f.write('<!doctype html><html><head><meta charset="utf-8"><title>nmdp view: loading</title></head>\n<body>\n')
        f.write(f'<script type="application/json" id="nmdp-view-data">{data}</script>\n')
        f.write("<script>" + bundle.replace("</script", "<\\/script") + "</script>\n</body></html>\n")

main()
