// Contact points with their force arrows, and the trunk's path, for one run.
import * as THREE from "three";

const POINT_RADIUS = 0.015; // m
const SMALLEST_ARROW = 0.005; // m: shorter arrows are hidden

export function buildContacts(run, look) {
  const group = new THREE.Group();
  const c = run.contacts.names.length;
  const points = run.contacts.points;
  const forces = run.contacts.forces;
  const markers = [];
  const arrows = [];
  const color = look.tint ? look.tint.clone() : new THREE.Color(0xe03131);
  for (let k = 0; k < c && points; k++) {
    const marker = new THREE.Mesh(new THREE.SphereGeometry(POINT_RADIUS, 12, 8),
      new THREE.MeshBasicMaterial({ color, transparent: look.opacity < 1, opacity: look.opacity }));
    markers.push(marker);
    group.add(marker);
    const arrow = new THREE.ArrowHelper(new THREE.Vector3(0, 0, 1), new THREE.Vector3(), 0.1, color.getHex());
    arrow.line.material.transparent = arrow.cone.material.transparent = look.opacity < 1;
    arrow.line.material.opacity = arrow.cone.material.opacity = look.opacity;
    arrows.push(arrow);
    group.add(arrow);
  }
  const direction = new THREE.Vector3();
  const origin = new THREE.Vector3();

  // newtonsPerMetre: an arrow of 1 m stands for this force.
  function setFrame(frame, newtonsPerMetre, showForces) {
    for (let k = 0; k < markers.length; k++) {
      const p = (frame * c + k) * 3;
      origin.set(points[p], points[p + 1], points[p + 2]);
      markers[k].position.copy(origin);
      const arrow = arrows[k];
      if (!forces || !showForces) { arrow.visible = false; continue; }
      direction.set(forces[p], forces[p + 1], forces[p + 2]);
      const length = direction.length() / newtonsPerMetre;
      arrow.visible = length > SMALLEST_ARROW && Number.isFinite(length);
      if (!arrow.visible) continue;
      arrow.position.copy(origin);
      arrow.setDirection(direction.normalize());
      arrow.setLength(length, Math.min(0.05, 0.3 * length), Math.min(0.025, 0.15 * length));
    }
  }
  return { group, setFrame };
}

export function buildPath(run, look) {
  const b = run.base.position;
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute("position", new THREE.BufferAttribute(new Float32Array(b), 3));
  const color = look.tint ? look.tint.clone() : new THREE.Color(0x1c7ed6);
  return new THREE.Line(geometry, new THREE.LineBasicMaterial({ color, transparent: look.opacity < 1, opacity: look.opacity }));
}
