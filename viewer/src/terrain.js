// The terrain grid as one mesh: each node coloured by its material (sand patches apart from rigid
// ground) shaded by its height, with grid lines about every 0.5 m so motion over flat ground shows.
import * as THREE from "three";

const DEFAULT_GROUND = [0.55, 0.56, 0.52];
const GRID_LINE_SPACING = 0.5; // m

export function buildTerrain(terrain) {
  const [nx, ny] = terrain.size;
  const [x0, y0] = terrain.origin;
  const [dx, dy] = terrain.spacing;
  const h = terrain.heights;
  let lo = Infinity;
  let hi = -Infinity;
  for (const z of h) { if (z < lo) lo = z; if (z > hi) hi = z; }
  const range = hi - lo > 1e-6 ? hi - lo : 1;

  const positions = new Float32Array(nx * ny * 3);
  const colors = new Float32Array(nx * ny * 3);
  const materialColors = terrain.materials.map((m) => m.color || DEFAULT_GROUND);
  for (let j = 0; j < ny; j++) {
    for (let i = 0; i < nx; i++) {
      const k = j * nx + i;
      positions.set([x0 + i * dx, y0 + j * dy, h[k]], k * 3);
      const base = (terrain.material && materialColors[terrain.material[k]]) || DEFAULT_GROUND;
      // Lower ground darker, higher lighter: 0.75..1.15 of the material's colour.
      const shade = 0.75 + 0.4 * (h[k] - lo) / range;
      colors.set(base.map((c) => Math.min(1, c * shade)), k * 3);
    }
  }
  const index = [];
  for (let j = 0; j + 1 < ny; j++) {
    for (let i = 0; i + 1 < nx; i++) {
      const a = j * nx + i;
      index.push(a, a + 1, a + nx + 1, a, a + nx + 1, a + nx);
    }
  }
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute("position", new THREE.BufferAttribute(positions, 3));
  geometry.setAttribute("color", new THREE.BufferAttribute(colors, 3));
  geometry.setIndex(index);
  geometry.computeVertexNormals();
  const surface = new THREE.Mesh(geometry, new THREE.MeshStandardMaterial({
    vertexColors: true, roughness: 0.95, metalness: 0, side: THREE.DoubleSide,
    polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1,
  }));

  const lines = [];
  const stepI = Math.max(1, Math.round(GRID_LINE_SPACING / dx));
  const stepJ = Math.max(1, Math.round(GRID_LINE_SPACING / dy));
  const node = (i, j) => [x0 + i * dx, y0 + j * dy, h[j * nx + i]];
  for (let j = 0; j < ny; j += stepJ) {
    for (let i = 0; i + 1 < nx; i++) lines.push(...node(i, j), ...node(i + 1, j));
  }
  for (let i = 0; i < nx; i += stepI) {
    for (let j = 0; j + 1 < ny; j++) lines.push(...node(i, j), ...node(i, j + 1));
  }
  const lineGeometry = new THREE.BufferGeometry();
  lineGeometry.setAttribute("position", new THREE.Float32BufferAttribute(lines, 3));
  const grid = new THREE.LineSegments(lineGeometry,
    new THREE.LineBasicMaterial({ color: 0x000000, transparent: true, opacity: 0.18 }));

  const group = new THREE.Group();
  group.add(surface, grid);
  return { group, lowest: lo, highest: hi };
}
