// The chain the solver uses, end to end on a robot: ∂V/∂θ from the model's dV/dξ and the contact
// Jacobian equals central differences of V(θ) through forward kinematics, for every model's
// derivative path (analytic Coulomb, analytic RBF geometry), on a floating and a planar base.
#include "contact_models/coulomb_model.hpp"
#include "contact_models/rbf_function.hpp"
#include "multibody/kinematics.hpp"
#include "solver/contact_kinematics.hpp"
#include "terrain/terrain_factory.hpp"
#include "test_support.hpp"

namespace nmdp::test {
namespace {

std::vector<ContactPoint> quadrupedFeet(const Model& model) {
  std::vector<ContactPoint> feet;
  for (const char* name : {"FL_foot", "FR_foot", "RL_foot", "RR_foot"})
    feet.push_back({name, model.linkIndex(name), Vec3::Zero(), 0.02, Vec3::UnitZ(), Vec3::UnitY()});
  return feet;
}

// A small RBF with a polynomial tail, so that both features matter everywhere.
std::unique_ptr<ContactModel> syntheticRbf() {
  RbfParameters p;
  p.spec.scaling = Eigen::Vector2d(5.0, 1.0);
  p.centres.resize(6, 2);
  p.centres << -0.05, -0.5, -0.05, 0.5, -0.02, 0.0, 0.0, -0.3, 0.0, 0.3, 0.05, 0.0;
  std::mt19937 rng(5);
  p.weights = randomVector(rng, 6 * 3 * 4, 50.0).reshaped(6, 12);
  p.polynomial = randomVector(rng, 3 * 12, 20.0).reshaped(3, 12);
  return std::make_unique<PlanarWrenchModel>(std::make_shared<RbfFunction>(p), PlanarGeometry{0.15, 0.1, 0.02}, "rbf");
}

// Standing-like configuration with the lowest foot `depth` below the terrain z = 0.
Eigen::VectorXd nearGround(const Model& model, const std::vector<ContactPoint>& feet, std::mt19937& rng, double depth) {
  Eigen::VectorXd q = randomVector(rng, model.nq, 0.15);
  const int z = model.dofIndex("base_z");
  for (int i = 0; i < model.nq; ++i)
    if (model.dof_names[i].find("knee") != std::string::npos) q[i] -= 1.0;
    else if (model.dof_names[i].find("thigh") != std::string::npos) q[i] += 0.5;
  Data data(model);
  forwardKinematics(model, data, q);
  double lowest = 1e9;
  for (const ContactPoint& c : feet) lowest = std::min(lowest, linkPoint(model, data, c.link, c.offset).z() - c.radius);
  q[z] -= lowest - depth;
  return q;
}

void expectChainMatchesFiniteDifferences(const Model& model, const ContactModel& contact_model, const Terrain& terrain,
                                         double depth, uint32_t seed) {
  const std::vector<ContactPoint> feet = quadrupedFeet(model);
  std::mt19937 rng(seed);
  const Eigen::VectorXd q = nearGround(model, feet, rng, depth);
  const int C = static_cast<int>(feet.size()), K = contact_model.vertexCount();
  Data data(model);
  auto evaluate = [&](const Eigen::VectorXd& x, bool derivatives) {
    forwardKinematics(model, data, x);
    std::vector<ContactFrame> frames(C);
    for (int c = 0; c < C; ++c) contactFrame(model, data, feet[c], frames[c]);
    std::vector<ContactWrenches> out(C);
    for (ContactWrenches& o : out) o.resize(K);
    contact_model.evaluate(frames, terrain, out, derivatives);
    return out;
  };
  const std::vector<ContactWrenches> at_q = evaluate(q, true);
  std::vector<Mat6X> J(C, Mat6X(6, model.nq));
  forwardKinematics(model, data, q);
  for (int c = 0; c < C; ++c) contactJacobian(model, data, feet[c], J[c]);

  double scale = 0;
  for (const ContactWrenches& w : at_q) scale = std::max(scale, w.V.cwiseAbs().maxCoeff());
  ASSERT_GT(scale, 1.0) << "the feet must be loaded for the check to mean anything";
  // Every contact's V as one vector of q, differentiated by central differences (test_support.hpp).
  const auto stacked = [&](const Eigen::VectorXd& x) {
    const std::vector<ContactWrenches> w = evaluate(x, false);
    Eigen::VectorXd out(6 * K * C);
    for (int c = 0; c < C; ++c) out.segment(6 * K * c, 6 * K) = w[c].V.reshaped();
    return out;
  };
  const Eigen::MatrixXd fd = centralDifference(stacked, q, 1e-7);
  for (int j = 0; j < model.nq; ++j) {
    for (int c = 0; c < C; ++c) {
      Mat6X chain(6, K);
      vertexDerivative(at_q[c], J[c], j, chain);
      const Mat6X numeric = fd.col(j).segment(6 * K * c, 6 * K).reshaped(6, K);
      EXPECT_LT((chain - numeric).cwiseAbs().maxCoeff(), 1e-5 * scale) << model.dof_names[j] << " contact " << c;
    }
  }
}

TEST(ContactChain, CoulombOnTiltedPlaneFloatingBase) {
  const Model model = loadUrdf(quadrupedUrdf());
  const auto coulomb = makeCoulombModel({{"k", 1e6}, {"p", 2}}, ConfigContext{"test", ""});
  const auto plane = makeTerrain({{"type", "plane"}, {"normal", {0.1, -0.05, 1.0}}}, ConfigContext{"test", ""});
  expectChainMatchesFiniteDifferences(model, *coulomb, *plane, -0.01, 1);
}

TEST(ContactChain, RbfOnHillsFloatingBase) {
  const Model model = loadUrdf(quadrupedUrdf());
  const auto hills = makeTerrain({{"type", "procedural"}, {"slope", {0.05, -0.03}},
                                  {"hills", {{{"centre", {0.2, 0.1}}, {"height", 0.03}, {"width", 0.3}}}}},
                                 ConfigContext{"test", ""});
  expectChainMatchesFiniteDifferences(model, *syntheticRbf(), *hills, -0.02, 2);
}

TEST(ContactChain, RbfPlanarBase) {
  UrdfOptions planar;
  planar.base = BaseType::Planar;
  const Model model = loadUrdf(quadrupedUrdf(), planar);
  const auto plane = makeTerrain({{"type", "plane"}}, ConfigContext{"test", ""});
  expectChainMatchesFiniteDifferences(model, *syntheticRbf(), *plane, -0.03, 3);
}

}  // namespace
}  // namespace nmdp::test
