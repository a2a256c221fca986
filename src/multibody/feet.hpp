// Foot detection: one contact sphere per leg, found from the URDF's collision geometry.
//
// Definitions (all evaluated at q = 0 with the base at the world origin, after fixed and locked
// joints are merged):
//  * Legs are the subtrees hanging off the trunk body (the links welded to the root link) through a
//    movable joint. If the URDF models the base itself as joints between massless, geometry-free
//    links with a single child (RoboSimian's _pinocchio.urdf: virtual0 → virtual1 → virtual2 →
//    torso), the trunk is the first body below them that has mass, geometry or branches. Sensor frames (imu) welded to the trunk are part of the root body, so they are
//    never legs. A subtree with no collision geometry at all is not a leg (unless no subtree has
//    any, then every subtree gets a radius-0 foot at its main chain's leaf origin), and neither is
//    one whose foot would lie above the trunk link origin (an arm, a head, a pan-tilt sensor), as
//    long as at least one leg remains.
//  * A leg's main chain is the path from its first link to one leaf link, the leaf chosen by
//    (most movable joints on the path, leaf link carries collision geometry, largest distance from
//    the leg's first link at q = 0). Side branches (A1's massless *_thigh_shoulder cylinder, our
//    quadruped's *_knee_rotor) are off the main chain and are ignored.
//  * The leg's direction d is gravity's direction when the leg hangs down at q = 0 (the first-link
//    → leaf vector within 60° of gravity: quadrupeds, A1, Solo-12), otherwise that vector itself
//    (RoboSimian, whose limbs stretch out sideways at q = 0). The foot is the collision geometry of
//    the main chain reaching farthest along d (the lowest one for a hanging leg, the distal end for
//    a stretched one); near ties (1e-6 m) go to the more distal link.
//  * The contact sphere of that geometry:
//      sphere    its centre and radius;
//      cylinder  whose axis is within 45° of d: the sphere inscribed in its end, i.e. radius
//                min(r, length/2) with its centre that far inside the end cap, so the sphere's tip
//                is the end cap's centre (the contact does not reach beyond the collision shape);
//                a cylinder lying across d (wheel-like): its centre, radius r;
//      box       the face most aligned with d: the sphere of radius min(half extents) touching
//                that face at its centre from inside;
//      mesh      an STL (binary or ASCII) read from CollisionGeometry::mesh_file, scaled and
//                placed: a cap estimate at the mesh's extreme point along d. The vertices within
//                δ of it form a cap; its widest vertex (half-width a from the cap's centroid axis,
//                height h) gives R = (a² + h²)/(2h), exact for a spherical cap; δ is the largest of
//                depth/2, depth/2^1.5, ... whose cap has not passed the equator (h ≤ R), and R is
//                capped at the mesh's half-width (a flat end gets the inscribed sphere). The
//                sphere touches the extreme point: centre = cap axis + (extreme − R) along d.
//                A mesh that cannot be read (absent, not STL, truncated) counts as a point at its
//                link's origin: if that is the foot, the foot is the link origin with radius 0 and
//                `warning` says so (`nmdp inspect` prints it on stderr).
#pragma once
#include <string>
#include <vector>

#include "multibody/contact_point.hpp"
#include "multibody/model.hpp"

namespace nmdp {

struct FootContact {
  // The contact sphere, named after its link, with its leg axis from legAxisOf.
  ContactPoint point;
  // How it was found: "sphere", "cylinder end", "cylinder side", "box face", "mesh cap", or
  // "link origin" (fallback, radius 0: unreadable foot mesh, or a robot without collision geometry).
  std::string source;
  std::string warning;  // non-empty when a fallback was used (e.g. the foot mesh is unreadable)
};

// One foot per leg, in URDF link order (the order of Model::links). Never throws for an
// unreadable mesh (see `warning`); returns an empty list for a robot without legs.
std::vector<FootContact> detectFeet(const Model& model);

// The contact points of detectFeet's feet.
std::vector<ContactPoint> footContactPoints(const Model& model);

}  // namespace nmdp
