#include "multibody/feet.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "multibody/data.hpp"
#include "multibody/kinematics.hpp"
#include "multibody/stl_mesh.hpp"

namespace nmdp {

namespace {

constexpr double kTieTolerance = 1e-6;     // m: supports this close count as equal (distal link wins)
constexpr double kHangingCosine = 0.5;     // leg within 60° of gravity: it hangs, use gravity
constexpr double kCapAxisCosine = 0.7071;  // cylinder axis within 45° of d: contact at an end cap

// A mesh's vertices in its link frame (scaled and placed), or the reason it could not be read.
struct MeshVertices {
  std::vector<Vec3> points;
  std::string error;
};

class MeshCache {
 public:
  // The geometry's vertices in its link frame; each file is read once per detectFeet call.
  MeshVertices get(const CollisionGeometry& g) {
    auto it = raw_.find(g.mesh_file);
    if (it == raw_.end()) {
      Raw entry;
      if (g.mesh_file.empty()) {
        entry.error = "mesh file not found";
      } else {
        try {
          entry.vertices = readStl(g.mesh_file).vertices;
          if (entry.vertices.empty()) entry.error = g.mesh_file + ": STL has no triangles";
        } catch (const std::exception& e) {
          entry.error = e.what();
        }
      }
      it = raw_.emplace(g.mesh_file, std::move(entry)).first;
    }
    MeshVertices out;
    out.error = it->second.error;
    out.points.reserve(it->second.vertices.size());
    for (const Vec3& v : it->second.vertices) out.points.push_back(g.translation + g.rotation * v.cwiseProduct(g.mesh_scale));
    return out;
  }

 private:
  struct Raw {
    std::vector<Vec3> vertices;
    std::string error;
  };
  std::map<std::string, Raw> raw_;
};

// Extreme value of x·d over a geometry (link frame, d unit in the link frame).
double support(const CollisionGeometry& g, const Vec3& d, const MeshVertices* mesh) {
  const double c = g.translation.dot(d);
  const Vec3 dg = g.rotation.transpose() * d;  // d in the geometry frame
  switch (g.shape) {
    case CollisionGeometry::Shape::Sphere:
      return c + g.radius;
    case CollisionGeometry::Shape::Box:
      return c + 0.5 * (std::abs(dg.x()) * g.size.x() + std::abs(dg.y()) * g.size.y() + std::abs(dg.z()) * g.size.z());
    case CollisionGeometry::Shape::Cylinder: {
      const double ca = std::min(1.0, std::abs(dg.z()));
      return c + 0.5 * g.length * ca + g.radius * std::sqrt(std::max(0.0, 1.0 - ca * ca));
    }
    case CollisionGeometry::Shape::Mesh: {
      if (!mesh || !mesh->error.empty()) return 0.0;  // unreadable: a point at the link origin
      double best = -std::numeric_limits<double>::infinity();
      for (const Vec3& p : mesh->points) best = std::max(best, p.dot(d));
      return best;
    }
  }
  return c;
}

struct Sphere {
  Vec3 center = Vec3::Zero();
  double radius = 0.0;
  std::string source;
  std::string warning;
};

// Contact sphere at the extreme of a mesh along d (link frame). See feet.hpp.
//
// Cap estimator: the vertices within δ of the extreme point form a cap; its widest vertex lies at
// lateral distance a from the cap's axis (through the centroid of the cap) and height h above the
// extreme point, and a sphere through it and the extreme point has R = (a² + h²) / 2h, exactly, for
// any vertex of a spherical cap. δ is the largest of depth/2, depth/2^1.5, ... with h ≤ R (the cap
// has not passed the equator): the whole lower hemisphere of a spherical foot, which makes the
// tessellation irrelevant. The widest direction is used, so for a wheel-like foot (Solo-12: a disc
// of radius 16 mm, 4 mm wide, with rounded edges) R is the rolling radius. R is capped at the
// mesh's half-width around that axis (a flat end gets the inscribed sphere).
Sphere meshFoot(const std::vector<Vec3>& pts, const Vec3& d) {
  double ext = -std::numeric_limits<double>::infinity(), low = std::numeric_limits<double>::infinity();
  for (const Vec3& p : pts) {
    ext = std::max(ext, p.dot(d));
    low = std::min(low, p.dot(d));
  }
  const double depth = ext - low;
  auto lateral = [&](const Vec3& p) -> Vec3 { return p - p.dot(d) * d; };
  auto capAxis = [&](double delta) {
    Vec3 c = Vec3::Zero();
    int n = 0;
    for (const Vec3& p : pts)
      if (ext - p.dot(d) <= delta) {
        c += lateral(p);
        ++n;
      }
    return Vec3(c / std::max(n, 1));
  };
  Sphere out;
  out.source = "mesh cap";
  if (!(depth > 1e-12)) {  // a flat mesh across d
    out.center = capAxis(0.0) + ext * d;
    out.warning = "flat mesh across the contact direction: radius 0";
    return out;
  }
  double delta = depth / 2, radius = 0.0;
  Vec3 axis = Vec3::Zero();
  for (int k = 0; k < 40; ++k, delta /= std::sqrt(2.0)) {
    axis = capAxis(delta);
    // The cap's widest vertex (the lowest one on ties): half-width a at height h above the extreme.
    double a = -1.0, h = 0.0;
    for (const Vec3& p : pts) {
      const double hp = ext - p.dot(d);
      if (hp > delta) continue;
      const double ap = (lateral(p) - axis).norm();
      if (ap > a * (1 + 1e-9) || (ap >= a * (1 - 1e-9) && hp < h)) {
        a = ap;
        h = hp;
      }
    }
    h = std::max(h, 1e-12 * depth);
    radius = (a * a + h * h) / (2 * h);
    if (h <= radius) break;  // the widest vertex is below the equator: a sphere cap
  }
  double half_width = 0.0;
  for (const Vec3& p : pts) half_width = std::max(half_width, (lateral(p) - axis).norm());
  out.radius = std::min(radius, half_width);
  out.center = axis + (ext - out.radius) * d;
  return out;
}

// Contact sphere of a geometry at its extreme along d (link frame). See feet.hpp.
Sphere footSphere(const CollisionGeometry& g, const Vec3& d, const MeshVertices* mesh) {
  Sphere out;
  const Vec3 dg = g.rotation.transpose() * d;
  switch (g.shape) {
    case CollisionGeometry::Shape::Sphere:
      out.center = g.translation;
      out.radius = g.radius;
      out.source = "sphere";
      break;
    case CollisionGeometry::Shape::Cylinder: {
      const Vec3 axis = g.rotation.col(2);
      if (std::abs(dg.z()) >= kCapAxisCosine) {
        const double s = dg.z() > 0 ? 1.0 : -1.0;
        out.radius = std::min(g.radius, 0.5 * g.length);
        out.center = g.translation + s * (0.5 * g.length - out.radius) * axis;
        out.source = "cylinder end";
      } else {
        out.center = g.translation;
        out.radius = g.radius;
        out.source = "cylinder side";
      }
      break;
    }
    case CollisionGeometry::Shape::Box: {
      int i;
      dg.cwiseAbs().maxCoeff(&i);
      const double s = dg[i] > 0 ? 1.0 : -1.0;
      const Vec3 half = 0.5 * g.size;
      out.radius = half.minCoeff();
      out.center = g.translation + g.rotation.col(i) * (s * (half[i] - out.radius));
      out.source = "box face";
      break;
    }
    case CollisionGeometry::Shape::Mesh:
      if (!mesh || !mesh->error.empty()) {
        out.center = Vec3::Zero();
        out.radius = 0.0;
        out.source = "link origin";
        out.warning = "foot mesh could not be read (" + (mesh ? mesh->error : std::string("no mesh")) +
                      "): the foot is the link origin with radius 0";
      } else {
        out = meshFoot(mesh->points, d);
      }
      break;
  }
  return out;
}

double snap(double x) { return std::abs(x) < 1e-12 ? 0.0 : x; }

struct Leg {
  int root = -1;
  std::vector<int> chain;  // leg root ... leaf
  FootContact foot;
  bool has_geometry = false;
  double height = 0.0;  // foot's lowest point above the root link origin (along −gravity)
};

// Every link's world pose at q = 0 with the base at the world origin.
struct LinkPoses {
  std::vector<Mat3> R;
  std::vector<Vec3> p;
};

LinkPoses linkPosesAtZero(const Model& model) {
  const int nl = static_cast<int>(model.links.size());
  Data data(model);
  forwardKinematics(model, data, Eigen::VectorXd::Zero(model.nq));
  LinkPoses poses{std::vector<Mat3>(nl), std::vector<Vec3>(nl)};
  for (int i = 0; i < nl; ++i) linkPose(model, data, i, poses.R[i], poses.p[i]);
  return poses;
}

// The trunk: the root body or, when the URDF models the base itself as joints between massless,
// geometry-free links (RoboSimian's _pinocchio.urdf: virtual0 → virtual1 → virtual2 → torso),
// the first body below it that carries something or branches. Returns {body, link}.
std::pair<int, int> findTrunk(const Model& model) {
  const int nl = static_cast<int>(model.links.size());
  int trunk_body = model.links[model.root_link].body;
  int trunk_link = model.root_link;
  for (;;) {
    std::vector<int> children;
    bool bare = true;
    for (int l = 0; l < nl; ++l) {
      const Link& link = model.links[l];
      if (link.body == trunk_body) {
        if (!link.collisions.empty() || link.mass > 0) bare = false;
      } else if (link.parent_link >= 0 && model.links[link.parent_link].body == trunk_body) {
        children.push_back(l);
      }
    }
    if (!bare || children.size() != 1) break;
    trunk_link = children[0];
    trunk_body = model.links[trunk_link].body;
  }
  return {trunk_body, trunk_link};
}

// Main chain of the leg rooted at link r: the leaf with the most movable joints, then carrying
// geometry, then farthest.
int mainLeaf(const Model& model, const LinkPoses& poses, int r) {
  int best_leaf = -1, best_moves = -1, best_geom = -1;
  double best_dist = -1;
  std::vector<int> stack{r};
  while (!stack.empty()) {
    const int l = stack.back();
    stack.pop_back();
    const Link& link = model.links[l];
    for (auto it = link.child_links.rbegin(); it != link.child_links.rend(); ++it) stack.push_back(*it);
    if (!link.child_links.empty()) continue;
    int moves = 0;
    for (int a = l;; a = model.links[a].parent_link) {
      moves += model.links[a].parent_joint_movable ? 1 : 0;
      if (a == r) break;
    }
    const int geom = link.collisions.empty() ? 0 : 1;
    const double dist = (poses.p[l] - poses.p[r]).norm();
    const bool better = moves > best_moves || (moves == best_moves && geom > best_geom) ||
                        (moves == best_moves && geom == best_geom && dist > best_dist + kTieTolerance);
    if (better) {
      best_leaf = l;
      best_moves = moves;
      best_geom = geom;
      best_dist = dist;
    }
  }
  return best_leaf;
}

// The collision geometry of the chain reaching farthest along d, as {chain position, geometry
// index}; near ties go to the more distal link. {-1, -1} when the chain has none.
std::pair<int, int> farthestGeometry(const Model& model, const LinkPoses& poses, const std::vector<int>& chain,
                                     const Vec3& d, MeshCache& meshes) {
  struct Candidate {
    int pos, geom;
    double support;
  };
  std::vector<Candidate> candidates;
  for (size_t k = 0; k < chain.size(); ++k) {
    const int l = chain[k];
    const Vec3 dl = poses.R[l].transpose() * d;
    const auto& cols = model.links[l].collisions;
    for (size_t j = 0; j < cols.size(); ++j) {
      MeshVertices mesh;
      if (cols[j].shape == CollisionGeometry::Shape::Mesh) mesh = meshes.get(cols[j]);
      candidates.push_back({static_cast<int>(k), static_cast<int>(j), poses.p[l].dot(d) + support(cols[j], dl, &mesh)});
    }
  }
  if (candidates.empty()) return {-1, -1};
  double top = -std::numeric_limits<double>::infinity();
  for (const Candidate& c : candidates) top = std::max(top, c.support);
  const Candidate* best = nullptr;
  for (const Candidate& c : candidates) {
    if (c.support < top - kTieTolerance) continue;
    if (!best || c.pos > best->pos || (c.pos == best->pos && c.support > best->support)) best = &c;
  }
  return {best->pos, best->geom};
}

// The leg rooted at link r, with its foot (link index, offset, radius, how it was found) and height.
Leg legFrom(const Model& model, const LinkPoses& poses, const Vec3& g, int trunk_link, int r, MeshCache& meshes) {
  const std::vector<Mat3>& Rw = poses.R;
  const std::vector<Vec3>& pw = poses.p;
  Leg leg;
  leg.root = r;
  const int best_leaf = mainLeaf(model, poses, r);
  for (int a = best_leaf;; a = model.links[a].parent_link) {
    leg.chain.push_back(a);
    if (a == r) break;
  }
  std::reverse(leg.chain.begin(), leg.chain.end());

  // The leg's direction: gravity if it hangs down at q = 0, else toward its leaf.
  const Vec3 reach = pw[best_leaf] - pw[r];
  Vec3 d = g;
  if (reach.norm() > 1e-9 && reach.normalized().dot(g) < kHangingCosine) d = reach.normalized();
  const auto [foot_pos, foot_geom] = farthestGeometry(model, poses, leg.chain, d, meshes);

  FootContact& foot = leg.foot;
  if (foot_pos < 0) {
    foot.point.link = best_leaf;
    foot.source = "link origin";
    foot.warning = "no collision geometry on the leg: the foot is the leaf link origin with radius 0";
    leg.height = -(pw[best_leaf] - pw[trunk_link]).dot(g);
  } else {
    const int l = leg.chain[foot_pos];
    const CollisionGeometry& geom = model.links[l].collisions[foot_geom];
    const Vec3 dl = Rw[l].transpose() * d;
    MeshVertices mesh;
    if (geom.shape == CollisionGeometry::Shape::Mesh) mesh = meshes.get(geom);
    const Sphere s = footSphere(geom, dl, &mesh);
    foot.point.link = l;
    foot.point.offset = s.center.unaryExpr([](double x) { return snap(x); });
    foot.point.radius = s.radius;
    foot.source = s.source;
    foot.warning = s.warning;
    leg.has_geometry = true;
    const Vec3 lowest = pw[l] + Rw[l] * s.center + s.radius * g;
    leg.height = -(lowest - pw[trunk_link]).dot(g);
  }
  foot.point.name = model.links[foot.point.link].name;
  return leg;
}

}  // namespace

std::vector<FootContact> detectFeet(const Model& model) {
  const int nl = static_cast<int>(model.links.size());
  if (nl == 0) return {};
  const LinkPoses poses = linkPosesAtZero(model);
  Vec3 g = model.gravity;
  g = g.norm() > 0 ? Vec3(g.normalized()) : Vec3(0, 0, -1);
  const auto [trunk_body, trunk_link] = findTrunk(model);
  auto inRoot = [&, trunk_body = trunk_body](int l) { return model.links[l].body == trunk_body; };

  MeshCache meshes;
  std::vector<Leg> legs;
  for (int r = 0; r < nl; ++r) {
    const Link& lr = model.links[r];
    if (inRoot(r) || lr.parent_link < 0 || !inRoot(lr.parent_link)) continue;
    legs.push_back(legFrom(model, poses, g, trunk_link, r, meshes));
  }

  // Subtrees without geometry are not legs, unless nothing has geometry.
  const bool any_geometry = std::any_of(legs.begin(), legs.end(), [](const Leg& l) { return l.has_geometry; });
  if (any_geometry)
    legs.erase(std::remove_if(legs.begin(), legs.end(), [](const Leg& l) { return !l.has_geometry; }), legs.end());
  // Subtrees whose foot is above the root link origin (arms, heads) are not legs, if a leg remains.
  const bool any_below = std::any_of(legs.begin(), legs.end(), [](const Leg& l) { return l.height < 0; });
  if (any_below) legs.erase(std::remove_if(legs.begin(), legs.end(), [](const Leg& l) { return l.height >= 0; }), legs.end());

  std::vector<FootContact> feet;
  feet.reserve(legs.size());
  for (Leg& leg : legs) {
    ContactPoint& point = leg.foot.point;
    point.leg_axis = legAxisOf(model, point.link, point.offset, point.radius);
    feet.push_back(std::move(leg.foot));
  }
  return feet;
}

std::vector<ContactPoint> footContactPoints(const Model& model) {
  std::vector<ContactPoint> out;
  for (const FootContact& f : detectFeet(model)) out.push_back(f.point);
  return out;
}

}  // namespace nmdp
