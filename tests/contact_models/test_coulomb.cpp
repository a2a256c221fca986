// The smooth Coulomb cone (DESIGN.md §7.1): dV/dξ against central finite differences of evaluate()
// on flat, tilted, overhanging and curved terrain (paraboloid and ball, so that ∂n/∂p ≠ 0), at and
// around contact onset; the physics of the vertices (friction ratio μ, cone axis along n, normal
// force k (d^p + ζ), torque (−r n) × F); the documented defaults; parameter validation.
#include <algorithm>
#include <cmath>

#include "contact_models/coulomb_model.hpp"
#include "common/input_error.hpp"
#include "contact_derivative_check.hpp"
#include "terrain/plane.hpp"
#include "test_support.hpp"
#include "test_terrains.hpp"

namespace nmdp::test {
namespace {

ConfigContext context() { return {"scene.json: contacts.model", ""}; }

CoulombModel defaultModel() { return CoulombModel(CoulombParameters{}); }

CoulombParameters coulombParameters(double mu, int K, double k, double p, double zeta) {
  return CoulombParameters{mu, K, k, p, zeta};
}

ContactWrenches evaluateOne(const ContactModel& model, const ContactFrame& frame, const Terrain& terrain,
                            bool derivatives) {
  std::vector<ContactWrenches> out(1);
  out[0].resize(model.vertexCount());
  model.evaluate({frame}, terrain, out, derivatives);
  return out[0];
}

// A frame whose sphere of radius r penetrates `terrain` by `depth` (negative: hovers above it) at
// horizontal position (x, y), found by moving the centre along z (φ is monotone in z for these
// terrains) with a few Newton steps; the leg axis and lateral are arbitrary (unused).
ContactFrame frameAt(const Terrain& terrain, double x, double y, double r, double depth) {
  ContactFrame f;
  f.radius = r;
  f.position = Vec3(x, y, 0.0);
  TerrainQuery q;
  for (int it = 0; it < 50; ++it) {
    terrain.query(f.position, q, true);
    const double residual = q.distance - (r - depth);
    if (std::abs(residual) < 1e-15) break;
    f.position.z() -= residual / q.gradient.z();
  }
  f.leg_axis = Vec3(0.2, -0.1, 1.0).normalized();
  f.lateral = Vec3(0.1, 1.0, 0.05).normalized();
  return f;
}

// Checks every dV/dξ_i against central differences of evaluate() (contact_derivative_check.hpp):
// translations move the centre, rotations turn the link-fixed axes about it (which must change nothing).
void checkDerivatives(const ContactModel& model, const Terrain& terrain, const ContactFrame& frame,
                      const std::string& label, double tol = 1e-6) {
  SCOPED_TRACE(label);
  // Step: the central difference of k d³ errs by k ε², relative ε²/(3d²) to its slope: ε = 1e-4 d.
  TerrainQuery q;
  terrain.query(frame.position, q, false);
  const double depth = frame.radius - q.distance;
  const ContactWrenches w0 = evaluateOne(model, frame, terrain, false);
  const double scale = w0.V.cwiseAbs().maxCoeff();
  VertexDerivativeCheck check;
  check.translation_step = depth > 0 ? std::clamp(1e-4 * depth, 1e-9, 1e-6) : 1e-6;
  check.rotation_step = 1e-4;
  check.tolerance = tol;
  check.scale_floor = 1e-9 * scale;  // some directions are ~0: relative to the largest derivative entry
  const VertexDerivativeResult r = checkVertexDerivative(model, {frame}, terrain, check, label);
  EXPECT_EQ(r.analytic[0].V, w0.V) << "V must not depend on whether derivatives are requested";
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(r.analytic[0].dV[i].cwiseAbs().maxCoeff(), 0.0) << "rotation " << i << " must not change V";
    EXPECT_LE(r.numeric[0].dV[i].cwiseAbs().maxCoeff(), 1e-14 * scale) << "rotation " << i;
  }
}

// ---------------------------------------------------------------------------------------------
// Tangent basis.

TEST(CoulombTangentBasis, OrthonormalRightHandedAndExactDerivative) {
  std::mt19937 rng(7);
  std::vector<Vec3> normals = {Vec3::UnitZ(), Vec3::UnitX(), Vec3::UnitY(), -Vec3::UnitZ(),
                               Vec3(0.3, -0.2, 1.0).normalized(), Vec3(1.0, 1.0, -0.4).normalized(),
                               Vec3(0.2, 0.1, -1.0).normalized()};
  for (int i = 0; i < 50; ++i) normals.push_back(Vec3(randomVector(rng, 3, 1.0)).normalized());
  for (const Vec3& n : normals) {
    SCOPED_TRACE(n.transpose());
    Vec3 t1, t2;
    Mat3 dt1, dt2;
    tangentBasis(n, t1, t2, &dt1, &dt2);
    EXPECT_NEAR(t1.norm(), 1.0, 1e-14);
    EXPECT_NEAR(t2.norm(), 1.0, 1e-14);
    EXPECT_NEAR(t1.dot(t2), 0.0, 1e-14);
    EXPECT_NEAR(t1.dot(n), 0.0, 1e-14);
    EXPECT_NEAR(t2.dot(n), 0.0, 1e-14);
    EXPECT_LE((t1.cross(t2) - n).norm(), 1e-14);
    if (std::abs(n.z() + 0.5) < 1e-3) continue;  // the branch switch
    auto f = [&](const Eigen::VectorXd& m) {
      Vec3 a, b;
      tangentBasis(Vec3(m), a, b);
      Eigen::VectorXd out(6);
      out << a, b;
      return out;
    };
    const Eigen::MatrixXd fd = centralDifference(f, n, 1e-6);
    Eigen::MatrixXd analytic(6, 3);
    analytic << dt1, dt2;
    EXPECT_LE((analytic - fd).cwiseAbs().maxCoeff(), 1e-8);
  }
  Vec3 t1, t2;
  tangentBasis(Vec3::UnitZ(), t1, t2);
  EXPECT_EQ(t1, Vec3::UnitX());
  EXPECT_EQ(t2, Vec3::UnitY());
}

// ---------------------------------------------------------------------------------------------
// The test terrains' own derivatives (so that the model's checks rest on exact inputs).

TEST(CoulombTestTerrains, DerivativesMatchFiniteDifferences) {
  const ParaboloidTerrain parab(0.8, -0.5);
  const BallTerrain ball(Vec3(0.1, -0.2, -0.5), 0.5);
  const std::vector<std::pair<const Terrain*, Vec3>> cases = {{&parab, Vec3(0.3, -0.4, 0.1)},
                                                              {&ball, Vec3(0.3, 0.1, 0.05)}};
  for (const auto& [terrain_case, p] : cases) {
    const Terrain* terrain = terrain_case;  // a structured binding cannot be captured before C++20 (clang)
    TerrainQuery q;
    terrain->query(p, q, true);
    auto f = [&](const Eigen::VectorXd& x) {
      TerrainQuery qq;
      terrain->query(Vec3(x), qq, false);
      Eigen::VectorXd out(4);
      out << qq.distance, qq.normal;
      return out;
    };
    const Eigen::MatrixXd fd = centralDifference(f, p, 1e-6);
    EXPECT_LE((fd.row(0).transpose() - q.gradient).cwiseAbs().maxCoeff(), 1e-8) << terrain->describe();
    EXPECT_LE((fd.bottomRows(3) - q.normal_jacobian).cwiseAbs().maxCoeff(), 1e-8) << terrain->describe();
  }
}

// ---------------------------------------------------------------------------------------------
// dV/dξ against finite differences.

TEST(CoulombDerivative, IsAnalytic) {
  const CoulombModel model = defaultModel();
  EXPECT_EQ(model.derivative(), DerivativeSupport::Analytic);
  EXPECT_EQ(model.vertexCount(), 6);
  EXPECT_NE(model.describe().find("coulomb"), std::string::npos);
}

TEST(CoulombDerivative, FlatPlane) {
  const CoulombModel model = defaultModel();
  const PlaneTerrain plane(Vec3::UnitZ(), 0.0);
  for (double depth : {3.5e-3, 1e-3, 1e-2}) checkDerivatives(model, plane, frameAt(plane, 0.3, -0.1, 0.02, depth),
                                                             "flat, depth " + std::to_string(depth));
}

TEST(CoulombDerivative, TiltedPlane) {
  const CoulombModel model = defaultModel();
  const PlaneTerrain plane(Vec3(0.3, -0.2, 1.0), 0.05);
  for (double depth : {3.5e-3, 1e-3, 1e-2}) checkDerivatives(model, plane, frameAt(plane, -0.2, 0.4, 0.02, depth),
                                                             "tilted, depth " + std::to_string(depth));
  // Steep slope and an overhang (the tangent basis's other branch).
  const PlaneTerrain steep(Vec3(1.0, 0.5, 0.2), 0.0), ceiling(Vec3(0.2, 0.1, -1.0), -1.0);
  for (const PlaneTerrain* t : {&steep, &ceiling}) {
    ContactFrame f;
    f.radius = 0.02;
    f.position = t->normal() * (t->offset() + f.radius - 2e-3) + Vec3(0.1, 0.2, 0.3).cross(t->normal());
    checkDerivatives(model, *t, f, t->describe());
  }
}

TEST(CoulombDerivative, NearContactOnset) {
  CoulombParameters p2;
  p2.p = 2.0;
  const CoulombModel model = defaultModel(), model_p2(p2);
  const PlaneTerrain tilted(Vec3(0.3, -0.2, 1.0), 0.0);
  const ParaboloidTerrain parab(0.8, -0.5);
  for (const ContactModel* m : {static_cast<const ContactModel*>(&model), static_cast<const ContactModel*>(&model_p2)})
    for (const Terrain* t : {static_cast<const Terrain*>(&tilted), static_cast<const Terrain*>(&parab)}) {
      const std::string name = m->describe() + " on " + t->describe();
      checkDerivatives(*m, *t, frameAt(*t, 0.25, 0.3, 0.02, 1e-4), name + ", d = 1e-4");
      checkDerivatives(*m, *t, frameAt(*t, 0.25, 0.3, 0.02, 1e-5), name + ", d = 1e-5");
    }
}

TEST(CoulombDerivative, JustOutsideOnlyZetaActs) {
  const CoulombModel model = defaultModel();
  const double kz = model.parameters().k * model.parameters().zeta;
  // On a plane nothing changes within the air gap: dV = 0 exactly, V = k ζ cone.
  const PlaneTerrain tilted(Vec3(0.3, -0.2, 1.0), 0.0);
  const ContactFrame above = frameAt(tilted, 0.1, 0.1, 0.02, -1e-4);
  const ContactWrenches w = evaluateOne(model, above, tilted, true);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(w.dV[i].cwiseAbs().maxCoeff(), 0.0) << i;
  EXPECT_NEAR(w.V.col(0).tail<3>().dot(tilted.normal()), kz, 1e-15 * kz);
  const ContactWrenches numeric = centralVertexDerivative(model, {above}, tilted, 1e-6, 1e-6)[0];
  for (int i = 3; i < 6; ++i) EXPECT_LE(numeric.dV[i].cwiseAbs().maxCoeff(), 1e-12 * kz) << i;
  // On curved terrain only the direction of the cone moves (∂n/∂p), with magnitude k ζ.
  const ParaboloidTerrain parab(0.8, -0.5);
  const BallTerrain ball(Vec3(0.0, 0.0, -1.0), 1.0);
  checkDerivatives(model, parab, frameAt(parab, 0.25, 0.3, 0.02, -1e-4), "paraboloid, air gap 1e-4");
  checkDerivatives(model, parab, frameAt(parab, -0.3, 0.2, 0.02, -0.05), "paraboloid, air gap 5 cm");
  checkDerivatives(model, ball, frameAt(ball, 0.3, 0.2, 0.02, -1e-4), "ball, air gap 1e-4");
}

TEST(CoulombDerivative, CurvedTerrainRandomStates) {
  std::mt19937 rng(42);
  const ParaboloidTerrain parab(0.8, -0.5);
  const BallTerrain ball(Vec3(0.05, -0.1, -0.6), 0.6);
  std::uniform_real_distribution<double> depth(5e-4, 1e-2);
  const CoulombParameters other = coulombParameters(1.1, 7, 3e6, 2.5, 1e-6);
  const CoulombModel model = defaultModel(), model_other(other);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::VectorXd xy = randomVector(rng, 2, 0.4);
    const double r = 0.01 + 0.03 * (trial % 3);
    const double d = depth(rng);
    const ContactModel& m = trial % 2 ? static_cast<const ContactModel&>(model_other) : model;
    checkDerivatives(m, parab, frameAt(parab, xy[0], xy[1], r, d), "paraboloid trial " + std::to_string(trial));
    checkDerivatives(m, ball, frameAt(ball, 0.5 * xy[0], 0.5 * xy[1], r, d), "ball trial " + std::to_string(trial));
    // ∂n/∂p ≠ 0 is really exercised: the force directions move along the surface.
    TerrainQuery q;
    parab.query(frameAt(parab, xy[0], xy[1], r, d).position, q, true);
    EXPECT_GT(q.normal_jacobian.norm(), 0.1);
  }
}

TEST(CoulombDerivative, BatchEqualsSingleEvaluations) {
  const CoulombModel model = defaultModel();
  const ParaboloidTerrain parab(0.8, -0.5);
  std::vector<ContactFrame> frames = {frameAt(parab, 0.1, 0.2, 0.02, 3e-3), frameAt(parab, -0.3, 0.1, 0.02, -1e-3),
                                      frameAt(parab, 0.2, -0.2, 0.015, 1e-4)};
  std::vector<ContactWrenches> out(frames.size());
  for (ContactWrenches& o : out) o.resize(model.vertexCount());
  model.evaluate(frames, parab, out, true);
  for (size_t b = 0; b < frames.size(); ++b) {
    const ContactWrenches single = evaluateOne(model, frames[b], parab, true);
    EXPECT_EQ(out[b].V, single.V);
    for (int i = 0; i < 6; ++i) EXPECT_EQ(out[b].dV[i], single.dV[i]);
  }
}

// ---------------------------------------------------------------------------------------------
// Physics of the vertices.

void checkCone(const CoulombModel& model, const Terrain& terrain, const ContactFrame& frame, const std::string& label) {
  SCOPED_TRACE(label);
  const CoulombParameters& c = model.parameters();
  TerrainQuery q;
  terrain.query(frame.position, q, false);
  const Vec3 n = q.normal;
  const double d = std::max(0.0, frame.radius - q.distance);
  const double expected_normal = c.k * (std::pow(d, c.p) + c.zeta);
  const ContactWrenches w = evaluateOne(model, frame, terrain, false);
  ASSERT_EQ(w.V.cols(), c.K);
  Vec3 axis = Vec3::Zero();
  for (int i = 0; i < c.K; ++i) {
    const Vec3 F = w.V.col(i).tail<3>();
    const double Fn = F.dot(n);
    const Vec3 Ft = F - Fn * n;
    EXPECT_NEAR(Fn, expected_normal, 1e-12 * expected_normal) << "vertex " << i;
    EXPECT_NEAR(Ft.norm() / Fn, c.mu, 1e-12) << "vertex " << i;
    EXPECT_LE((w.V.col(i).head<3>() - (-frame.radius * n).cross(F)).norm(), 1e-12 * F.norm()) << "vertex " << i;
    // The vertices are spread evenly: consecutive tangential directions turn by 2π/K about n.
    const Vec3 Ft_next = w.V.col((i + 1) % c.K).tail<3>() - Fn * n;
    EXPECT_NEAR(std::atan2(Ft.cross(Ft_next).dot(n), Ft.dot(Ft_next)), 2 * M_PI / c.K, 1e-12) << "vertex " << i;
    axis += F;
  }
  EXPECT_LE(axis.cross(n).norm(), 1e-12 * axis.norm()) << "cone axis " << axis.transpose() << " not along n";
  EXPECT_GT(axis.dot(n), 0.0);
  EXPECT_NEAR(axis.norm(), c.K * expected_normal, 1e-12 * c.K * expected_normal);
}

TEST(CoulombPhysics, ConeShapeAndNormalForce) {
  const CoulombParameters p2 = coulombParameters(0.4, 4, 1e6, 2.0, 1e-4);
  const CoulombModel model = defaultModel(), model_p2(p2);
  const PlaneTerrain flat, tilted(Vec3(0.3, -0.2, 1.0), 0.05);
  const ParaboloidTerrain parab(0.8, -0.5);
  for (const CoulombModel* m : {&model, &model_p2})
    for (const Terrain* t : {static_cast<const Terrain*>(&flat), static_cast<const Terrain*>(&tilted),
                             static_cast<const Terrain*>(&parab)})
      for (double depth : {-1e-2, -1e-4, 0.0, 1e-4, 1e-3, 3.5e-3, 1e-2})
        checkCone(*m, *t, frameAt(*t, 0.2, -0.15, 0.02, depth),
                  m->describe() + " on " + t->describe() + ", depth " + std::to_string(depth));
}

TEST(CoulombPhysics, NormalForceFollowsPowerLaw) {
  // Independent of the implementation's arithmetic: F_n(d) − k ζ scales as d^p.
  const CoulombModel model = defaultModel();
  const PlaneTerrain flat;
  const double kz = 1e9 * 1e-10;
  auto normal = [&](double depth) {
    return evaluateOne(model, frameAt(flat, 0, 0, 0.02, depth), flat, false).V(5, 0);
  };
  EXPECT_NEAR(normal(-1e-3), kz, 1e-15);
  EXPECT_NEAR(normal(1e-3), 1e9 * 1e-9 + kz, 1e-9);
  EXPECT_NEAR(normal(2e-3), 1e9 * 8e-9 + kz, 1e-9);
  EXPECT_NEAR(normal(5e-3), 1e9 * 125e-9 + kz, 1e-8);
  EXPECT_NEAR((normal(4e-3) - kz) / (normal(2e-3) - kz), 8.0, 1e-6);
  EXPECT_NEAR(model.normalForce(3e-3), 1e9 * 27e-9 + kz, 1e-9);
  EXPECT_EQ(model.normalForce(-1.0), kz);
}

TEST(CoulombPhysics, DefaultsSinkTheQuadrupedAFewMillimetres) {
  const std::unique_ptr<ContactModel> built = makeCoulombModel(nlohmann::json::object(), context());
  ASSERT_NE(dynamic_cast<CoulombModel*>(built.get()), nullptr);
  const CoulombParameters c = static_cast<CoulombModel&>(*built).parameters();
  EXPECT_EQ(c.mu, 0.7);
  EXPECT_EQ(c.K, 6);
  EXPECT_EQ(c.k, 1e9);
  EXPECT_EQ(c.p, 3.0);
  EXPECT_EQ(c.zeta, 1e-10);
  const double mass = loadUrdf(quadrupedUrdf()).total_mass;
  EXPECT_NEAR(mass, 17.41, 0.5);
  // Each of the 4 feet carries m g / 4 when all its weight is on the cone (1ᵀw = 1).
  const double foot_load = mass * 9.81 / 4;
  const double depth = std::cbrt(foot_load / c.k - c.zeta);
  EXPECT_GT(depth, 2e-3);
  EXPECT_LT(depth, 5e-3);
  EXPECT_NEAR(depth, 3.49e-3, 0.02e-3);
  // The force in the air is tiny but nonzero.
  const CoulombModel model(c);
  EXPECT_GT(model.normalForce(0.0), 0.0);
  EXPECT_LT(model.normalForce(0.0), 0.01 * foot_load);
  EXPECT_NEAR(model.normalForce(depth), foot_load, 1e-9 * foot_load);
}

TEST(CoulombPhysics, OrientationOfTheLinkDoesNotMatter) {
  const CoulombModel model = defaultModel();
  const PlaneTerrain tilted(Vec3(0.3, -0.2, 1.0), 0.0);
  ContactFrame f = frameAt(tilted, 0.1, 0.1, 0.02, 2e-3);
  const Mat6X V = evaluateOne(model, f, tilted, false).V;
  f.leg_axis = Vec3(1, 0, 0);
  f.lateral = Vec3(0, 0, 1);
  f.lateral_rotates = false;
  EXPECT_EQ(evaluateOne(model, f, tilted, false).V, V);
}

// ---------------------------------------------------------------------------------------------
// Parameters.

TEST(CoulombParams, FactoryReadsEveryKey) {
  const nlohmann::json j = {{"type", "coulomb"}, {"mu", 0.5}, {"K", 8}, {"k", 2e6}, {"p", 2}, {"zeta", 1e-4}};
  const std::unique_ptr<ContactModel> m = makeCoulombModel(j, context());
  ASSERT_NE(dynamic_cast<CoulombModel*>(m.get()), nullptr);
  const CoulombParameters& c = static_cast<CoulombModel&>(*m).parameters();
  EXPECT_EQ(c.mu, 0.5);
  EXPECT_EQ(c.K, 8);
  EXPECT_EQ(c.k, 2e6);
  EXPECT_EQ(c.p, 2.0);
  EXPECT_EQ(c.zeta, 1e-4);
  EXPECT_EQ(m->vertexCount(), 8);
  EXPECT_EQ(kCoulombParameters, (std::vector<std::string>{"mu", "K", "k", "p", "zeta"}));
}

// The configuration the model reports is complete (the defaults of the keys not given) and builds
// the same model again.
TEST(CoulombParams, ConfigurationListsEveryParameterAndRebuildsTheSameModel) {
  const CoulombParameters defaults;
  const nlohmann::json reported = makeCoulombModel({{"type", "coulomb"}, {"mu", 0.4}}, context())->configuration();
  EXPECT_EQ(reported, nlohmann::json({{"type", "coulomb"}, {"mu", 0.4}, {"K", defaults.K}, {"k", defaults.k},
                                      {"p", defaults.p}, {"zeta", defaults.zeta}}));
  for (const std::string& key : kCoulombParameters) EXPECT_TRUE(reported.contains(key)) << key;
  const std::unique_ptr<ContactModel> again = makeCoulombModel(reported, context());
  EXPECT_EQ(again->configuration(), reported);
  const CoulombParameters& c = static_cast<CoulombModel&>(*again).parameters();
  EXPECT_EQ(c.mu, 0.4);
  EXPECT_EQ(c.K, defaults.K);
  EXPECT_EQ(c.k, defaults.k);
  EXPECT_EQ(c.p, defaults.p);
  EXPECT_EQ(c.zeta, defaults.zeta);
  // Non-default values survive a trip through JSON text.
  const nlohmann::json odd = {{"type", "coulomb"}, {"mu", 0.1 + 0.2}, {"K", 7}, {"k", 1.0 / 3.0}, {"p", 2.5}, {"zeta", 1e-7 / 3}};
  const nlohmann::json text = nlohmann::json::parse(makeCoulombModel(odd, context())->configuration().dump());
  EXPECT_EQ(text, odd);
}

TEST(CoulombParams, BadParametersNameTheKey) {
  const std::vector<std::pair<nlohmann::json, std::string>> bad = {
      {{{"mu", -1}}, "contacts.model.mu"},      {{{"mu", 0}}, "contacts.model.mu"},
      {{{"mu", "high"}}, "contacts.model.mu"},  {{{"K", 2}}, "contacts.model.K"},
      {{{"K", 6.5}}, "contacts.model.K"},       {{{"k", 0}}, "contacts.model.k"},
      {{{"k", -1e9}}, "contacts.model.k"},      {{{"p", 1.5}}, "contacts.model.p"},
      {{{"zeta", 0}}, "contacts.model.zeta"},   {{{"zeta", -1e-9}}, "contacts.model.zeta"},
      {{{"muu", 0.7}}, "contacts.model.muu"},   {{{"radius", 0.02}}, "contacts.model.radius"},
  };
  for (const auto& [params, key] : bad) {
    SCOPED_TRACE(params.dump());
    try {
      makeCoulombModel(params, context());
      ADD_FAILURE() << "expected InputError";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("scene.json: " + key + ":"), std::string::npos) << what;
    }
  }
  try {
    makeCoulombModel({{"muu", 0.7}}, context());
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean 'mu'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(makeCoulombModel(nlohmann::json::array(), context()), InputError);
  CoulombParameters c;
  c.K = 2;
  EXPECT_THROW(CoulombModel{c}, std::invalid_argument);
}

}  // namespace
}  // namespace nmdp::test
