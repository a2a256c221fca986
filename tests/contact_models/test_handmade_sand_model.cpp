// The project's hand-made sand model, data/granular/handmade_sand_rbf.h5 (written by
// scripts/make_handmade_sand_model.py), loaded exactly as a scene's {"type": "rbf", "file": ...}:
//  * it loads, with 26 vertices, at most 40 centres and the geometry the script documents;
//  * an upright foot 1.5 cm deep bears 30-150 N (the quadruped's 42.7 N per foot by design), and no
//    combination of vertices with 1ᵀw ≤ 1 bears more than the best vertex;
//  * it is exactly zero (V and dV) at and above the surface, its cut-off;
//  * the capacity grows with depth on a grid of depths and tilts, and with the tilt;
//  * its traction is friction-like, as in sand: at a normal load of 20-70 % of the capacity the
//    polytope offers 0.5-0.8 times that load horizontally (and at most twice it at 10 %, where the
//    published RoboSimian samples reach 1.77), so a lightly loaded foot is not held in the sand;
//  * the force passes through the sphere centre (torque about it ≈ 0);
//  * dV/dξ matches central differences.
#include <algorithm>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "contact_models/rbf_function.hpp"
#include "contact_models/rbf_model.hpp"
#include "terrain/plane.hpp"
#include "planar_foot.hpp"
#include "test_support.hpp"

namespace nmdp::test {
namespace {

const char* kModelFolder = "data/granular";
const char* kModelFile = "handmade_sand_rbf.h5";
constexpr double kFootRadius = 0.02;  // the quadruped's feet
constexpr double kQuarterWeight = 17.4 * 9.81 / 4;

std::unique_ptr<ContactModel> loadModel() {
  const ConfigContext ctx{"test: contacts.model", sourcePath(kModelFolder)};
  return makeRbfModel({{"type", "rbf"}, {"file", kModelFile}}, ctx);
}

ContactFrame foot(double depth, double angle) { return planarFoot(kFootRadius, depth, angle); }

ContactWrenches evaluate(const ContactModel& model, const ContactFrame& frame, bool derivatives = false) {
  const PlaneTerrain ground;
  std::vector<ContactWrenches> out(1);
  out[0].resize(model.vertexCount());
  model.evaluate({frame}, ground, out, derivatives);
  return out[0];
}

// The largest normal force among the vertices (rows 3..5 of V are the force; the normal is z).
double capacity(const ContactModel& model, double depth, double angle) {
  return evaluate(model, foot(depth, angle)).V.row(5).maxCoeff();
}

TEST(HandmadeSandModel, LoadsWithTheDocumentedLayout) {
  const std::unique_ptr<ContactModel> model = loadModel();
  EXPECT_EQ(model->vertexCount(), 26);
  EXPECT_EQ(model->derivative(), DerivativeSupport::Analytic);
  const RbfModelFile file = readRbfHdf5(sourcePath(kModelFolder) + "/" + kModelFile);
  EXPECT_LE(file.parameters.centres.rows(), 40);
  EXPECT_EQ(file.parameters.weights.cols(), 3 * 26);
  EXPECT_EQ(file.parameters.spec.kernel, RbfKernel::ThinPlate);
  EXPECT_EQ(file.geometry.cutoff, 0.0);
  EXPECT_GT(file.geometry.cutoff_width, 0.0);
  EXPECT_DOUBLE_EQ(file.geometry.torque_centre, kFootRadius);
}

TEST(HandmadeSandModel, UprightFootAtOneAndAHalfCentimetresCarriesAQuarterOfTheRobot) {
  const std::unique_ptr<ContactModel> model = loadModel();
  const Mat6X V = evaluate(*model, foot(-0.015, 0.0)).V;
  const double best_vertex = V.row(5).maxCoeff();
  EXPECT_GE(best_vertex, 30.0);
  EXPECT_LE(best_vertex, 150.0);
  EXPECT_NEAR(best_vertex, kQuarterWeight, 0.1 * kQuarterWeight) << "the design point of the model";
  // The polytope is {V w : w ≥ 0, 1ᵀw ≤ 1}: a linear function peaks at a vertex (or the origin).
  std::mt19937 rng(7);
  std::exponential_distribution<double> draw(1.0);
  for (int trial = 0; trial < 2000; ++trial) {
    Eigen::VectorXd w(V.cols() + 1);  // the last entry is the slack 1 − 1ᵀw
    for (Eigen::Index j = 0; j < w.size(); ++j) w[j] = std::pow(draw(rng), 4.0);  // favour sparse mixes
    w /= w.sum();
    EXPECT_LE(V.row(5).dot(w.head(V.cols())), best_vertex + 1e-9);
  }
}

TEST(HandmadeSandModel, IsZeroAtAndAboveTheSurface) {
  const std::unique_ptr<ContactModel> model = loadModel();
  for (double depth : {0.0, 1e-4, 0.003, 0.01, 0.05, 0.5})
    for (double angle : {-0.6, 0.0, 0.6}) {
      const ContactWrenches w = evaluate(*model, foot(depth, angle), true);
      EXPECT_EQ(w.V.cwiseAbs().maxCoeff(), 0.0) << "depth " << depth << ", angle " << angle;
      for (const Mat6X& d : w.dV) EXPECT_EQ(d.cwiseAbs().maxCoeff(), 0.0) << "depth " << depth;
    }
}

TEST(HandmadeSandModel, CapacityGrowsWithDepthAndWithTilt) {
  const std::unique_ptr<ContactModel> model = loadModel();
  for (double angle : {-0.9, -0.45, 0.0, 0.3, 0.45, 0.9}) {
    double previous = 0.0;
    for (int i = 1; i <= 40; ++i) {  // 2.5 mm to 10 cm
      const double depth = -0.0025 * i;
      const double c = capacity(*model, depth, angle);
      EXPECT_GT(c, previous) << "depth " << depth << ", angle " << angle;
      previous = c;
    }
  }
  for (double depth : {-0.01, -0.015, -0.03, -0.06}) {
    EXPECT_GT(capacity(*model, depth, 0.6), capacity(*model, depth, 0.0)) << "depth " << depth;
    EXPECT_GT(capacity(*model, depth, -0.6), capacity(*model, depth, 0.0)) << "depth " << depth;
  }
}

// The largest |F_x| of the polytope {V w : w ≥ 0, 1ᵀw ≤ 1} at F_z = load, over load (the foot on
// flat ground: x is the sagittal forward axis, z the normal). The polygon's widest point at a
// height lies on one of its edges, a segment between two of its points (the vertices and the
// origin), and every such segment lies in it, so the maximum over all pairs is exact.
double traction(const Mat6X& V, double load) {
  std::vector<std::pair<double, double>> points{{0.0, 0.0}};
  for (Eigen::Index j = 0; j < V.cols(); ++j) points.emplace_back(V(3, j), V(5, j));
  double best = 0.0;
  for (const auto& [ax, az] : points)
    for (const auto& [bx, bz] : points) {
      if (az == load) best = std::max(best, std::abs(ax));
      if ((az - load) * (bz - load) < 0.0) best = std::max(best, std::abs(ax + (load - az) / (bz - az) * (bx - ax)));
    }
  return best / load;
}

TEST(HandmadeSandModel, TractionIsFrictionLikeAsInSand) {
  const std::unique_ptr<ContactModel> model = loadModel();
  for (double depth : {-0.02, -0.03, -0.05})
    for (double angle : {-0.8, 0.0, 0.8}) {
      const Mat6X V = evaluate(*model, foot(depth, angle)).V;
      const double capacity = V.row(5).maxCoeff();
      for (double share : {0.2, 0.4, 0.6, 0.7}) {
        const double t = traction(V, share * capacity);
        EXPECT_GE(t, 0.5) << "depth " << depth << ", angle " << angle << ", load " << share << " x capacity";
        EXPECT_LE(t, 0.8) << "depth " << depth << ", angle " << angle << ", load " << share << " x capacity";
      }
      EXPECT_LE(traction(V, 0.1 * capacity), 2.0) << "depth " << depth << ", angle " << angle
                                                   << ": a lightly loaded foot is held in the sand";
    }
}

TEST(HandmadeSandModel, ForcePassesThroughTheSphereCentre) {
  const std::unique_ptr<ContactModel> model = loadModel();
  for (double depth : {-0.01, -0.015, -0.03, -0.06})
    for (double angle : {-0.8, -0.3, 0.0, 0.5, 0.9}) {
      const Mat6X V = evaluate(*model, foot(depth, angle)).V;
      // The fit's τ error as a lever arm (at most 2.1 mm, at 1 cm and β = −0.8): well under the
      // 20 mm arm of a force applied at the foot point.
      const double arm = V.topRows(3).cwiseAbs().maxCoeff() / V.bottomRows(3).cwiseAbs().maxCoeff();
      EXPECT_LT(arm, 0.15 * kFootRadius) << "depth " << depth << ", angle " << angle;
    }
}

TEST(HandmadeSandModel, DerivativeMatchesCentralDifferences) {
  const std::unique_ptr<ContactModel> model = loadModel();
  const double eps = 1e-6;
  // Off the RBF centres, one in the cut-off band, tilted both ways, a foot rotated about z.
  struct Case {
    double depth, angle, yaw;
  };
  for (const Case& c : {Case{-0.015, 0.1, 0.0}, Case{-0.003, -0.2, 0.0}, Case{-0.033, 0.7, 0.3},
                        Case{-0.055, -0.45, -0.5}}) {
    ContactFrame frame = foot(c.depth, c.angle);
    const Mat3 yaw = Eigen::AngleAxisd(c.yaw, Vec3::UnitZ()).toRotationMatrix();
    frame.leg_axis = yaw * frame.leg_axis;
    frame.lateral = yaw * frame.lateral;
    const ContactWrenches exact = evaluate(*model, frame, true);
    double scale = 1e-9;
    for (const Mat6X& d : exact.dV) scale = std::max(scale, d.cwiseAbs().maxCoeff());
    for (int i = 0; i < 6; ++i) {
      ContactFrame plus = frame, minus = frame;
      if (i < 3) {  // rotation about world axis i around the sphere centre
        const Mat3 Rp = Eigen::AngleAxisd(eps, Vec3::Unit(i)).toRotationMatrix();
        const Mat3 Rm = Eigen::AngleAxisd(-eps, Vec3::Unit(i)).toRotationMatrix();
        plus.leg_axis = Rp * frame.leg_axis, plus.lateral = Rp * frame.lateral;
        minus.leg_axis = Rm * frame.leg_axis, minus.lateral = Rm * frame.lateral;
      } else {
        plus.position[i - 3] += eps;
        minus.position[i - 3] -= eps;
      }
      const Mat6X numeric = (evaluate(*model, plus).V - evaluate(*model, minus).V) / (2 * eps);
      EXPECT_LT((exact.dV[i] - numeric).cwiseAbs().maxCoeff() / scale, 1e-5)
          << "depth " << c.depth << ", angle " << c.angle << ", xi " << i;
    }
  }
}

}  // namespace
}  // namespace nmdp::test
