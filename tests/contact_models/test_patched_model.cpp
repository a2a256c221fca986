// The blended contact model of ground with material patches (contact_models/patched_model.hpp):
// its dV/dξ against central differences across the blending band (where the weights' gradients
// enter), V bit for bit the patch's model inside the patch and the default's outside, the weakest
// derivative support of its parts, and no allocation once warmed up.
#define NMDP_COUNT_MALLOC
#include <gtest/gtest.h>

#include <cmath>

#include "contact_derivative_check.hpp"
#include "contact_models/coulomb_model.hpp"
#include "contact_models/patched_model.hpp"
#include "contact_models/rbf_model.hpp"
#include "terrain/plane.hpp"
#include "test_allocation_counter.hpp"
#include "test_support.hpp"

namespace nmdp {
namespace {

using test::sourcePath;
using Vec2 = Eigen::Vector2d;

constexpr double kBlend = 0.05;  // m
// The pit: x ≥ 1 m, |y| ≤ 1 m.
std::shared_ptr<const MaterialLayout> pitLayout() {
  return std::make_shared<MaterialLayout>(
      std::vector<MaterialPatch>{{"pit", MaterialRegion::rectangle(Vec2(1.0, -1.0), Vec2(3.0, 1.0))}}, kBlend);
}

std::unique_ptr<ContactModel> sandModel() {
  return makeRbfModel({{"file", sourcePath("data/granular/rft_quadruped_rbf.h5")}}, ConfigContext{"test", ""});
}

std::unique_ptr<PatchedModel> pitModel() {
  std::vector<std::unique_ptr<ContactModel>> parts;
  parts.push_back(std::make_unique<CoulombModel>());
  parts.push_back(sandModel());
  return std::make_unique<PatchedModel>(pitLayout(), std::move(parts));
}

// Feet 1 cm deep (sphere radius 2 cm) with tilted legs, at x along the band and beyond it.
std::vector<ContactFrame> feetAt(const std::vector<double>& xs, double y = 0.1) {
  std::vector<ContactFrame> frames;
  for (size_t i = 0; i < xs.size(); ++i) {
    ContactFrame f;
    f.radius = 0.02;
    f.position = Vec3(xs[i], y + 0.01 * i, 0.01);
    f.leg_axis = Vec3(0.2 - 0.1 * i, 0.05 * i - 0.1, 1.0).normalized();
    f.lateral = Vec3(0.05 * i, 1.0, 0.0).normalized();
    frames.push_back(f);
  }
  return frames;
}

TEST(PatchedModel, VerticesAreTheMaterialsWeightedColumns) {
  const auto model = pitModel();
  const CoulombModel rigid;
  const auto sand = sandModel();
  EXPECT_EQ(model->vertexCount(), rigid.vertexCount() + sand->vertexCount());
  EXPECT_EQ(model->columnOffset(1), rigid.vertexCount());
  EXPECT_EQ(model->derivative(), DerivativeSupport::Analytic);
  const PlaneTerrain plane;
  // Deep inside the pit, outside it, and in the band (x = 1 m: half each).
  const std::vector<ContactFrame> frames = feetAt({1.5, 0.5, 1.0, 1.01});
  std::vector<ContactWrenches> out(frames.size()), a(frames.size()), b(frames.size());
  for (ContactWrenches& w : a) w.resize(rigid.vertexCount());
  for (ContactWrenches& w : b) w.resize(sand->vertexCount());
  model->evaluate(frames, plane, out, true);
  rigid.evaluate(frames, plane, a, true);
  sand->evaluate(frames, plane, b, true);
  const int K0 = rigid.vertexCount(), K1 = sand->vertexCount();
  // Inside: the sand's V and dV/dξ bit for bit, the rigid columns zero.
  EXPECT_TRUE((out[0].V.middleCols(K0, K1).array() == b[0].V.array()).all());
  EXPECT_TRUE((out[0].V.leftCols(K0).array() == 0.0).all());
  for (int i = 0; i < 6; ++i) EXPECT_TRUE((out[0].dV[i].middleCols(K0, K1).array() == b[0].dV[i].array()).all());
  // Outside: the default's.
  EXPECT_TRUE((out[1].V.leftCols(K0).array() == a[1].V.array()).all());
  EXPECT_TRUE((out[1].V.middleCols(K0, K1).array() == 0.0).all());
  for (int i = 0; i < 6; ++i) EXPECT_TRUE((out[1].dV[i].leftCols(K0).array() == a[1].dV[i].array()).all());
  // On the boundary: half of each.
  EXPECT_LT((out[2].V.leftCols(K0) - 0.5 * a[2].V).cwiseAbs().maxCoeff(), 1e-12 * a[2].V.cwiseAbs().maxCoeff());
  EXPECT_LT((out[2].V.middleCols(K0, K1) - 0.5 * b[2].V).cwiseAbs().maxCoeff(), 1e-12 * b[2].V.cwiseAbs().maxCoeff());
  EXPECT_GT(b[2].V.cwiseAbs().maxCoeff(), 1.0);  // the sand pushes back at 1 cm (a real check)
}

TEST(PatchedModel, DerivativeMatchesCentralDifferencesAcrossTheBand) {
  const auto model = pitModel();
  const PlaneTerrain plane;
  // Across the band x ∈ [0.975, 1.025] and at a corner of the pit, where ∂w/∂x and ∂w/∂y are large
  // (up to 1.5 / (kBlend / 2) = 60 per m) and multiply V: steps of 1e-6 m and rad keep the
  // truncation error (h² V w''' ~ 1e-12 · 1e2 · 1e5) and rounding (1e-16 · 1e3 / 1e-6) far below
  // the 1e-6 relative tolerance the RBF's own check uses.
  test::VertexDerivativeCheck check;
  check.rotation_step = check.translation_step = 1e-6;
  check.tolerance = 1e-6;
  std::vector<ContactFrame> frames = feetAt({0.97, 0.985, 0.995, 1.0, 1.008, 1.02});
  const std::vector<ContactFrame> corner = feetAt({0.99, 1.005, 1.015}, 0.99);
  frames.insert(frames.end(), corner.begin(), corner.end());
  const test::VertexDerivativeResult r = test::checkVertexDerivative(*model, frames, plane, check, "across the band");
  EXPECT_LT(r.worst, 1e-6);
  // The weights' gradient is really exercised: the x derivative differs from w dV/dξ alone.
  const auto sand = sandModel();
  std::vector<ContactWrenches> sand_only(frames.size());
  for (ContactWrenches& w : sand_only) w.resize(sand->vertexCount());
  sand->evaluate(frames, plane, sand_only, true);
  EXPECT_GT((r.analytic[3].dV[3].rightCols(sand_only[3].V.cols()) - 0.5 * sand_only[3].dV[3]).cwiseAbs().maxCoeff(),
            10.0 * sand_only[3].V.cwiseAbs().maxCoeff());
}

TEST(PatchedModel, DerivativeSupportIsTheWeakestOfTheParts) {
  class NoDerivative : public CoulombModel {
   public:
    DerivativeSupport derivative() const override { return DerivativeSupport::None; }
  };
  std::vector<std::unique_ptr<ContactModel>> parts;
  parts.push_back(std::make_unique<CoulombModel>());
  parts.push_back(std::make_unique<NoDerivative>());
  const PatchedModel model(pitLayout(), std::move(parts));
  EXPECT_EQ(model.derivative(), DerivativeSupport::None);
  std::vector<std::unique_ptr<ContactModel>> wrong;
  wrong.push_back(std::make_unique<CoulombModel>());
  EXPECT_THROW(PatchedModel(pitLayout(), std::move(wrong)), std::invalid_argument);
}

TEST(PatchedModel, AllocatesNothingOnceWarmedUp) {
  const auto model = pitModel();
  const PlaneTerrain plane;
  const std::vector<ContactFrame> in_band = feetAt({0.99, 1.0, 1.01, 1.5});
  const std::vector<ContactFrame> outside = feetAt({0.2, 0.3, 0.4, 0.5});
  std::vector<ContactWrenches> out(4);
  for (const auto* frames : {&in_band, &outside}) model->evaluate(*frames, plane, out, true);
  test::alloc::malloc_calls = 0;
  test::alloc::counting = true;
  for (int k = 0; k < 3; ++k)
    for (const auto* frames : {&outside, &in_band})
      for (bool derivatives : {true, false}) model->evaluate(*frames, plane, out, derivatives);
  test::alloc::counting = false;
#if NMDP_COUNTS_MALLOC
  EXPECT_EQ(test::alloc::malloc_calls.load(), 0);
#endif
}

}  // namespace
}  // namespace nmdp
