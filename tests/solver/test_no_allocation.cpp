// DESIGN.md 12: "stepping allocates nothing once warmed up". Every multibody kernel the step
// solvers call per Newton iteration is run once to warm up and then once more while every heap
// allocation of this test binary is counted; the second call must allocate nothing.
//
// Counting: the global operator new family is replaced (std::vector, std::string, ...), and on
// glibc malloc/calloc/realloc/memalign/posix_memalign/aligned_alloc are interposed as well,
// because Eigen allocates its dynamic matrices with std::malloc, not operator new. Both only count
// while counting is on, i.e. around the measured call; the replacement (test_allocation_counter.hpp)
// lives in this test binary only.
#include "multibody/crba.hpp"
#include "multibody/kinematics.hpp"
#include "multibody/pbd_terms.hpp"
#include "multibody/rnea.hpp"
#include "multibody/rnea_derivatives.hpp"
#include "solver/ne_residual.hpp"
#include "test_support.hpp"

#define NMDP_COUNT_OPERATOR_NEW
#define NMDP_COUNT_MALLOC
#include "test_allocation_counter.hpp"

namespace nmdp::test {
namespace {

// Keeps the compiler from eliding an allocation whose pointer is otherwise unused.
const void* volatile g_sink = nullptr;
void sink(const void* p) { g_sink = p; }

#define EXPECT_NO_ALLOCATION(call)                                                                        \
  do {                                                                                                    \
    const AllocationCount count_ = allocationsOf([&] { call; });                                          \
    EXPECT_EQ(count_.total(), 0) << #call << ": " << count_.news << " operator new, " << count_.mallocs   \
                                 << " malloc-family calls after warm-up";                                 \
  } while (0)

// The counters themselves: a vector and an Eigen matrix created inside the window are seen.
TEST(NoAllocation, CounterSeesAllocations) {
  const AllocationCount vec = allocationsOf([] {
    std::vector<double> v(100, 1.0);
    sink(v.data());
  });
  EXPECT_GE(vec.news, 1);
#if NMDP_COUNTS_MALLOC
  const AllocationCount mat = allocationsOf([] {
    Eigen::MatrixXd m = Eigen::MatrixXd::Ones(20, 20);
    sink(m.data());
  });
  EXPECT_GE(mat.mallocs, 1) << "Eigen allocations must be counted";
#endif
}

class NoAllocation : public RobotTest {
 protected:
  void SetUp() override {
    RobotTest::SetUp();
    if (IsSkipped()) return;
    data = std::make_unique<Data>(model);
    const int n = model.nq;
    std::mt19937 rng(3);
    q = randomVector(rng, n, 1.0);
    qd = randomVector(rng, n, 2.0);
    qdd = randomVector(rng, n, 5.0);
    q_n = randomVector(rng, n, 1.0);
    qd_n = randomVector(rng, n, 1.0);
    theta = q_n + h * qd_n + randomVector(rng, n, 0.01);
    G.setZero(n);
    dG.setZero(n, n);
    grad.setZero(n);
    hess.setZero(n, n);
    J.setZero(6, n);
    BodyTransforms current, previous;
    forwardKinematics(model, *data, q_n - h * qd_n);
    bodyTransforms(model, *data, previous);
    forwardKinematics(model, *data, q_n);
    bodyTransforms(model, *data, current);
    inertialTargets(current, previous, 1.0, targets);
    // A point on the deepest body (the last in depth-first order is a leaf).
    contact_body = n - 1;
    wrench << 0.3, -0.2, 0.1, 5.0, -3.0, 40.0;
  }

  std::unique_ptr<Data> data;
  double h = 0.01;
  Eigen::VectorXd q, qd, qdd, q_n, qd_n, theta, G, grad;
  Eigen::MatrixXd dG, hess;
  Mat6X J;
  BodyTransforms targets;
  int contact_body = 0;
  Vec6 wrench;
};

// Negative control inside the library: constructing a Data allocates (std::vector and Eigen).
TEST_P(NoAllocation, CounterSeesLibraryAllocations) {
  std::unique_ptr<Data> fresh;
  const AllocationCount count = allocationsOf([&] { fresh = std::make_unique<Data>(model); });
  EXPECT_GE(count.news, 1);
#if NMDP_COUNTS_MALLOC
  EXPECT_GT(count.mallocs, count.news) << "Eigen's own mallocs inside the library must be counted";
#endif
}

TEST_P(NoAllocation, ForwardKinematics) { EXPECT_NO_ALLOCATION(forwardKinematics(model, *data, q)); }

TEST_P(NoAllocation, Rnea) { EXPECT_NO_ALLOCATION(rnea(model, *data, q, qd, qdd)); }

TEST_P(NoAllocation, Crba) { EXPECT_NO_ALLOCATION(crba(model, *data, q)); }

TEST_P(NoAllocation, RneaDerivatives) { EXPECT_NO_ALLOCATION(rneaDerivatives(model, *data, q, qd, qdd)); }

TEST_P(NoAllocation, NeInertialResidual) {
  EXPECT_NO_ALLOCATION(neInertialResidual(model, *data, theta, q_n, qd_n, h, G, nullptr));
}

TEST_P(NoAllocation, NeInertialResidualWithJacobian) {
  EXPECT_NO_ALLOCATION(neInertialResidual(model, *data, theta, q_n, qd_n, h, G, &dG));
}

TEST_P(NoAllocation, SpatialJacobian) {
  forwardKinematics(model, *data, q);
  const Vec3 point = data->p[contact_body] + Vec3(0.01, -0.02, 0.03);
  EXPECT_NO_ALLOCATION(spatialJacobian(model, *data, contact_body, point, J));
}

TEST_P(NoAllocation, AddJacobianTransposeWrenchDerivative) {
  forwardKinematics(model, *data, q);
  const Vec3 point = data->p[contact_body] + Vec3(0.01, -0.02, 0.03);
  EXPECT_NO_ALLOCATION(addJacobianTransposeWrenchDerivative(model, *data, contact_body, point, wrench, dG));
}

// The composite of the NE benchmark: inertial residual, then J_cᵀ f_c and (∂J_cᵀ/∂θ) f_c of one
// contact, all into preallocated G, dG, J.
TEST_P(NoAllocation, NeResidualWithContactAndJacobian) {
  EXPECT_NO_ALLOCATION({
    neInertialResidual(model, *data, theta, q_n, qd_n, h, G, &dG);
    const Vec3 point = data->p[contact_body];
    spatialJacobian(model, *data, contact_body, point, J);
    G.noalias() -= J.transpose() * wrench;
    addJacobianTransposeWrenchDerivative(model, *data, contact_body, point, -wrench, dG);
  });
}

TEST_P(NoAllocation, TransformEnergyWithGradientAndHessian) {
  forwardKinematics(model, *data, theta);
  EXPECT_NO_ALLOCATION(transformEnergy(model, *data, targets, h, &grad, &hess));
}

TEST_P(NoAllocation, TransformEnergyValueOnly) {
  forwardKinematics(model, *data, theta);
  EXPECT_NO_ALLOCATION(transformEnergy(model, *data, targets, h, nullptr, nullptr));
}

TEST_P(NoAllocation, GravityPotentialWithGradientAndHessian) {
  forwardKinematics(model, *data, theta);
  EXPECT_NO_ALLOCATION(gravityPotential(model, *data, &grad, &hess));
}

TEST_P(NoAllocation, BodyTransformsAndInertialTargets) {
  forwardKinematics(model, *data, theta);
  BodyTransforms current, out;
  bodyTransforms(model, *data, current);
  EXPECT_NO_ALLOCATION({
    bodyTransforms(model, *data, current);
    inertialTargets(current, targets, 1.0, out);
  });
}

INSTANTIATE_TEST_SUITE_P(Robots, NoAllocation, ::testing::ValuesIn(derivativeRobots()),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace nmdp::test
