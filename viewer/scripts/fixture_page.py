#!/usr/bin/python3
"""Development stand-in for `nmdp view`: writes a page (payload.md's format, version 1) from run files
of the current layout, with link poses and foot points from its own forward kinematics of the URDF's
collision shapes (fixed and revolute joints only).
Usage: fixture_page.py OUT.html RUN.h5 [RUN2.h5 ...]"""
import base64, json, math, os, sys
import xml.etree.ElementTree as ET
import h5py
import numpy as np

def arr(a, dtype):
    a = np.ascontiguousarray(a, dtype=dtype)
    return {"dtype": dtype, "shape": list(a.shape), "b64": base64.b64encode(a.astype("<" + a.dtype.str[1:]).tobytes()).decode()}

def rpy_to_quat(rpy):
    r, p, y = rpy[:, 0] / 2, rpy[:, 1] / 2, rpy[:, 2] / 2
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    return np.stack([sr*cp*cy - cr*sp*sy, cr*sp*cy + sr*cp*sy, cr*cp*sy - sr*sp*cy, cr*cp*cy + sr*sp*sy], axis=1)

def rot_rpy(r, p, y):
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return np.array([[cy*cp, cy*sp*sr - sy*cr, cy*sp*cr + sy*sr], [sy*cp, sy*sp*sr + cy*cr, sy*sp*cr - cy*sr], [-sp, cp*sr, cp*cr]])

def rot_axis(axis, angle):
    a = np.asarray(axis, float); a = a / np.linalg.norm(a)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K

def quat_of(R):
    w = math.sqrt(max(0.0, 1 + R[0, 0] + R[1, 1] + R[2, 2])) / 2
    x = math.copysign(math.sqrt(max(0.0, 1 + R[0, 0] - R[1, 1] - R[2, 2])) / 2, R[2, 1] - R[1, 2])
    y = math.copysign(math.sqrt(max(0.0, 1 - R[0, 0] + R[1, 1] - R[2, 2])) / 2, R[0, 2] - R[2, 0])
    z = math.copysign(math.sqrt(max(0.0, 1 - R[0, 0] - R[1, 1] + R[2, 2])) / 2, R[1, 0] - R[0, 1])
    return [x, y, z, w]

def origin_of(element):
    o = element.find("origin") if element is not None else None
    xyz = [float(v) for v in (o.get("xyz", "0 0 0") if o is not None else "0 0 0").split()]
    rpy = [float(v) for v in (o.get("rpy", "0 0 0") if o is not None else "0 0 0").split()]
    return np.array(xyz), rot_rpy(*rpy)

def urdf_model(urdf_path):
    root = ET.parse(urdf_path).getroot()
    links, joints = [], {}
    for link in root.findall("link"):
        visuals = []
        shapes = link.findall("visual") or link.findall("collision")
        source = "visual" if link.findall("visual") else "collision"
        for shape in shapes:
            g = shape.find("geometry")
            xyz, R = origin_of(shape)
            v = {"origin": list(xyz) + quat_of(R), "color": None, "source": source}
            if g.find("box") is not None: v.update(type="box", size=[float(x) for x in g.find("box").get("size").split()])
            elif g.find("sphere") is not None: v.update(type="sphere", radius=float(g.find("sphere").get("radius")))
            elif g.find("cylinder") is not None: v.update(type="cylinder", radius=float(g.find("cylinder").get("radius")), length=float(g.find("cylinder").get("length")))
            else: continue
            visuals.append(v)
        links.append({"name": link.get("name"), "visuals": visuals})
    for joint in root.findall("joint"):
        xyz, R = origin_of(joint)
        axis = joint.find("axis")
        joints[joint.find("child").get("link")] = (joint.get("name"), joint.find("parent").get("link"), joint.get("type"), xyz, R,
            [float(v) for v in axis.get("xyz").split()] if axis is not None else [1, 0, 0])
    return links, joints

def link_poses(links, joints, joint_names, q, base_pos, base_rpy):
    n = q.shape[0]
    poses = np.zeros((n, len(links), 7))
    for i in range(n):
        world = {}
        def pose(name):
            if name in world: return world[name]
            if name not in joints:
                world[name] = (base_pos[i], rot_rpy(*base_rpy[i]))
                return world[name]
            jname, parent, jtype, xyz, R, axis = joints[name]
            pp, pR = pose(parent)
            Rj = R
            if jtype in ("revolute", "continuous") and jname in joint_names:
                Rj = R @ rot_axis(axis, q[i, joint_names.index(jname)])
            world[name] = (pp + pR @ xyz, pR @ Rj)
            return world[name]
        for l, link in enumerate(links):
            p, R = pose(link["name"])
            poses[i, l] = list(p) + quat_of(R)
    return poses

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
    config = json.loads(f.attrs["config"])
    urdf = config["robot"]["urdf"]
    if os.path.exists(urdf):
        links, joints = urdf_model(urdf)
        poses = link_poses(links, joints, names, f["q"][:n], pos, f["base/rpy"][:n])
        link_names = [l["name"] for l in links]
        points = arr(np.stack([poses[:, link_names.index(c), :3] for c in cnames], axis=1), "float32")
        poses = arr(poses, "float32")
        warnings = []
    else:
        links = [{"name": "trunk", "visuals": [{"type": "box", "size": [0.4, 0.2, 0.1], "origin": [0, 0, 0, 0, 0, 0, 1], "color": None, "source": "inertia"}]}]
        poses = points = None
        warnings = [f"{os.path.basename(path)} has no /model/urdf and its URDF {urdf} is not found: the trunk is drawn as a box"]
    if status == "running":
        warnings.append(f"{os.path.basename(path)} was cut short (status 'running'): {n} committed rows")
    return {
        "label": f"{os.path.basename(path)}: {f.attrs.get('method', '?')}, dt = {float(f.attrs.get('dt', 0))*1000:g} ms",
        "file": os.path.abspath(path), "status": status, "warnings": warnings, "frames": n,
        "time": arr(time, "float64"),
        "links": links, "link_poses": poses,
        "base": {"position": arr(pos, "float32"), "quaternion": arr(quat, "float32")},
        "contacts": {"names": cnames, "points": points, "forces": arr(wrench[:, :, 3:6], "float32"), "normal_force": arr(wrench[:, :, 5], "float32")},
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
