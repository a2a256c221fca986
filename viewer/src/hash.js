// Hash parameters: #t=1.5&follow=0&camera=px,py,pz,tx,ty,tz&panel=0
//   t: the time shown first (s); follow=0: a fixed camera; camera: its position and target (world, m);
//   panel=0: no plot panel, controls or legend (the canvas fills the window: for tests and screenshots).
export function parseHash(hash) {
  const params = new URLSearchParams((hash || "").replace(/^#/, ""));
  const options = { t: null, follow: true, camera: null, panel: true };
  if (params.has("t")) {
    const t = Number(params.get("t"));
    if (Number.isFinite(t)) options.t = t;
  }
  if (params.has("follow")) options.follow = !["0", "false", "no"].includes(params.get("follow"));
  if (params.has("camera")) {
    const c = params.get("camera").split(",").map(Number);
    if (c.length === 6 && c.every(Number.isFinite)) options.camera = c;
  }
  if (params.has("panel")) options.panel = !["0", "false", "no"].includes(params.get("panel"));
  return options;
}
