// The robot of one run: a group per link holding its visuals (box, sphere, cylinder, mesh), posed
// per frame from link_poses (world), or, when the run has none, the first link at the trunk's pose.
import * as THREE from "three";
import { STLLoader } from "three/examples/jsm/loaders/STLLoader.js";
import { OBJLoader } from "three/examples/jsm/loaders/OBJLoader.js";
import { ColladaLoader } from "three/examples/jsm/loaders/ColladaLoader.js";

const DEFAULT_COLOR = [0.62, 0.64, 0.68, 1];
// A run without links is drawn as a box of about the quadruped's trunk (m).
const FALLBACK_TRUNK_SIZE = [0.4, 0.2, 0.1];

function primitiveGeometry(visual) {
  switch (visual.type) {
    case "box": return new THREE.BoxGeometry(...visual.size);
    case "sphere": return new THREE.SphereGeometry(visual.radius, 24, 16);
    case "cylinder": {
      // three's cylinders run along y; URDF's along the link's z.
      const geometry = new THREE.CylinderGeometry(visual.radius, visual.radius, visual.length, 24);
      geometry.rotateX(Math.PI / 2);
      return geometry;
    }
    default: return null;
  }
}

function meshObject(visual, material) {
  const bytes = visual.data && visual.data.data;
  if (!bytes) return null;
  const format = (visual.format || "").toLowerCase();
  let object;
  if (format === "stl") {
    const buffer = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
    object = new THREE.Mesh(new STLLoader().parse(buffer), material);
  } else if (format === "obj" || format === "dae") {
    const text = new TextDecoder().decode(bytes);
    if (format === "obj") {
      object = new OBJLoader().parse(text);
    } else {
      object = new ColladaLoader().parse(text, "").scene;
      // The loader turns a Z_UP asset to y-up; this world is z-up like URDF: undo that, and turn a
      // Y_UP asset to z-up instead.
      object.rotation.set(object.rotation.x !== 0 ? 0 : Math.PI / 2, 0, 0);
    }
    object.traverse((child) => { if (child.isMesh) child.material = material; });
  } else {
    throw new Error(`mesh format ${JSON.stringify(visual.format)} is not stl, obj or dae`);
  }
  if (visual.scale) object.scale.multiply(new THREE.Vector3(...visual.scale));
  return object;
}

function visualMaterial(color, look) {
  const c = color || DEFAULT_COLOR;
  const base = new THREE.Color(c[0], c[1], c[2]);
  if (look.tint) base.lerp(look.tint, 0.6);
  const opacity = (c[3] ?? 1) * look.opacity;
  return new THREE.MeshStandardMaterial({
    color: base, roughness: 0.7, metalness: 0.1,
    transparent: opacity < 1, opacity, depthWrite: opacity >= 1,
  });
}

function setOrigin(object, origin) {
  if (!origin) return;
  const wrapper = new THREE.Group();
  wrapper.position.set(origin[0], origin[1], origin[2]);
  wrapper.quaternion.set(origin[3], origin[4], origin[5], origin[6]);
  wrapper.add(object);
  return wrapper;
}

// look: {opacity (1 for run 0, 0.45 for overlaid runs), tint: THREE.Color | null}.
// Returns {group, setFrame(i)} and pushes a warning for each visual it cannot draw.
export function buildRobot(run, look, warnings) {
  const group = new THREE.Group();
  const linkGroups = [];
  const links = run.links.length > 0 ? run.links
    : [{ name: "trunk", visuals: [{ type: "box", size: FALLBACK_TRUNK_SIZE, origin: null, color: null }] }];
  for (const link of links) {
    const linkGroup = new THREE.Group();
    linkGroup.name = link.name;
    for (const visual of link.visuals) {
      const material = visualMaterial(visual.color, look);
      let object = null;
      try {
        if (visual.type === "mesh") {
          object = meshObject(visual, material);
        } else {
          const geometry = primitiveGeometry(visual);
          if (geometry) object = new THREE.Mesh(geometry, material);
        }
      } catch (e) {
        warnings.push(`${run.label}: link ${link.name}: a ${visual.type} visual cannot be drawn (${e.message})`);
      }
      if (!object) continue;
      linkGroup.add(setOrigin(object, visual.origin) || object);
    }
    linkGroups.push(linkGroup);
    group.add(linkGroup);
  }
  const poses = run.linkPoses;
  const count = links.length;
  // Without link poses only the first link (the trunk) can be placed: at the base pose.
  if (!poses) linkGroups.forEach((g, i) => { g.visible = i === 0; });

  function setFrame(frame) {
    if (poses) {
      for (let l = 0; l < count; l++) {
        const p = (frame * count + l) * 7;
        linkGroups[l].position.set(poses[p], poses[p + 1], poses[p + 2]);
        linkGroups[l].quaternion.set(poses[p + 3], poses[p + 4], poses[p + 5], poses[p + 6]);
      }
    } else {
      const b = run.base.position;
      linkGroups[0].position.set(b[frame * 3], b[frame * 3 + 1], b[frame * 3 + 2]);
      const q = run.base.quaternion;
      if (q) linkGroups[0].quaternion.set(q[frame * 4], q[frame * 4 + 1], q[frame * 4 + 2], q[frame * 4 + 3]);
    }
  }
  return { group, setFrame };
}
