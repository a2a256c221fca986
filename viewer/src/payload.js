// Reads the page's payload (the JSON in <script id="nmdp-view-data">, format "nmdp-view" version 1)
// and decodes its arrays ({dtype, shape, b64}, little-endian, C order) into typed arrays.

const DTYPES = { float32: Float32Array, float64: Float64Array, uint8: Uint8Array };

export class PayloadError extends Error {}

function decodeBase64(text) {
  const binary = atob(text);
  const bytes = new Uint8Array(binary.length);
  for (let i = 0; i < binary.length; i++) bytes[i] = binary.charCodeAt(i);
  return bytes;
}

// One array, checked against the shape the contract gives (null entries of `expected` match any
// length). Returns {data, shape} or null when the payload holds null.
export function decodeArray(value, what, expected) {
  if (value === null || value === undefined) return null;
  const Type = DTYPES[value.dtype];
  if (!Type) throw new PayloadError(`${what}: unknown dtype ${JSON.stringify(value.dtype)}`);
  if (!Array.isArray(value.shape) || !value.shape.every((n) => Number.isInteger(n) && n >= 0)) {
    throw new PayloadError(`${what}: shape is not a list of sizes`);
  }
  const bytes = decodeBase64(value.b64 || "");
  const count = value.shape.reduce((a, b) => a * b, 1);
  if (bytes.length !== count * Type.BYTES_PER_ELEMENT) {
    throw new PayloadError(`${what}: ${bytes.length} bytes for shape [${value.shape}] of ${value.dtype}`);
  }
  if (expected) {
    const ok = expected.length === value.shape.length &&
      expected.every((n, i) => n === null || n === value.shape[i]);
    if (!ok) throw new PayloadError(`${what}: shape [${value.shape}], expected [${expected.map((n) => n ?? "*")}]`);
  }
  return { data: new Type(bytes.buffer, 0, count), shape: value.shape };
}

function decodeRun(run, index) {
  const what = `runs[${index}]`;
  const n = run.frames;
  if (!Number.isInteger(n) || n < 1) throw new PayloadError(`${what}.frames: ${n} (need at least one frame)`);
  const time = decodeArray(run.time, `${what}.time`, [n]);
  const links = run.links || [];
  const linkPoses = decodeArray(run.link_poses, `${what}.link_poses`, [n, links.length, 7]);
  const base = {
    position: decodeArray(run.base && run.base.position, `${what}.base.position`, [n, 3]),
    quaternion: decodeArray(run.base && run.base.quaternion, `${what}.base.quaternion`, [n, 4]),
  };
  if (!base.position) throw new PayloadError(`${what}.base.position is missing`);
  const contacts = run.contacts || { names: [] };
  const c = (contacts.names || []).length;
  const joints = run.joints || { names: [], q: null };
  const series = run.series || {};
  const decoded = {
    label: run.label || `run ${index + 1}`,
    file: run.file || "",
    status: run.status || "",
    warnings: run.warnings || [],
    frames: n,
    time: time.data,
    links: links.map((link) => ({
      name: link.name,
      visuals: (link.visuals || []).map((v, k) => decodeVisual(v, `${what}.links[${link.name}].visuals[${k}]`)),
    })),
    linkPoses: linkPoses && linkPoses.data,
    base: { position: base.position.data, quaternion: base.quaternion && base.quaternion.data },
    contacts: {
      names: contacts.names || [],
      points: decodeArray(contacts.points, `${what}.contacts.points`, [n, c, 3]),
      forces: decodeArray(contacts.forces, `${what}.contacts.forces`, [n, c, 3]),
      normalForce: decodeArray(contacts.normal_force, `${what}.contacts.normal_force`, [n, c]),
    },
    joints: {
      names: joints.names || [],
      q: decodeArray(joints.q, `${what}.joints.q`, [n, (joints.names || []).length]),
    },
    series: {
      torsoHeight: decodeArray(series.torso_height, `${what}.series.torso_height`, [n]),
      forwardDistance: decodeArray(series.forward_distance, `${what}.series.forward_distance`, [n]),
    },
  };
  for (const key of ["points", "forces", "normalForce"]) {
    if (decoded.contacts[key]) decoded.contacts[key] = decoded.contacts[key].data;
  }
  if (decoded.joints.q) decoded.joints.q = decoded.joints.q.data;
  for (const key of ["torsoHeight", "forwardDistance"]) {
    if (decoded.series[key]) decoded.series[key] = decoded.series[key].data;
  }
  for (let i = 1; i < n; i++) {
    if (!(decoded.time[i] > decoded.time[i - 1])) {
      throw new PayloadError(`${what}.time does not increase at frame ${i}`);
    }
  }
  return decoded;
}

function decodeVisual(v, what) {
  const visual = { ...v };
  if (v.type === "mesh") visual.data = decodeArray(v.data, `${what}.data`, [null]);
  return visual;
}

function decodeTerrain(t) {
  if (!t) return null;
  const [nx, ny] = t.size || [];
  const heights = decodeArray(t.heights, "terrain.heights", [ny, nx]);
  const material = decodeArray(t.material, "terrain.material", [ny, nx]);
  return {
    description: t.description || "",
    origin: t.origin, spacing: t.spacing, size: [nx, ny],
    heights: heights.data,
    material: material && material.data,
    materials: t.materials || [],
  };
}

// The payload of this page, decoded: {generator, warnings, terrain, runs}.
export function readPayload(doc) {
  const element = doc.getElementById("nmdp-view-data");
  if (!element) throw new PayloadError("the page has no <script id=\"nmdp-view-data\"> payload");
  let json;
  try {
    json = JSON.parse(element.textContent);
  } catch (e) {
    throw new PayloadError(`the payload is not JSON: ${e.message}`);
  }
  if (json.format !== "nmdp-view") throw new PayloadError(`payload format ${JSON.stringify(json.format)}, expected "nmdp-view"`);
  if (json.version !== 1) throw new PayloadError(`payload version ${json.version}, this viewer reads version 1`);
  if (!Array.isArray(json.runs) || json.runs.length === 0) throw new PayloadError("the payload has no runs");
  return {
    generator: json.generator || "",
    warnings: json.warnings || [],
    terrain: decodeTerrain(json.terrain),
    runs: json.runs.map(decodeRun),
  };
}

// Index of the last frame with time <= t (frame 0 before the first time): runs hold their last pose
// after they end.
export function frameAt(time, t) {
  let lo = 0;
  let hi = time.length - 1;
  if (!(t >= time[0])) return 0;
  while (lo < hi) {
    const mid = (lo + hi + 1) >> 1;
    if (time[mid] <= t) lo = mid; else hi = mid - 1;
  }
  return lo;
}
