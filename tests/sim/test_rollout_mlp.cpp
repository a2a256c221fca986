// rollout (sim/rollout.hpp) with the MLP contact model (libtorch): every thread's simulation
// evaluates its own model instance, and 1 and 2 threads give the bits of a loop of steps.
#include <gtest/gtest.h>

#include <cstring>

#include "contact_model_files.hpp"
#include "scene_simulation.hpp"
#include "sim/rollout.hpp"

namespace nmdp {
namespace {

bool sameBits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
}

TEST(RolloutMlp, ThreadsGiveTheBitsOfALoopOfSteps) {
  const test::TempDir dir;
  const std::string mlp = test::writeRandomMlp(dir, "foot.h5");
  const SceneConfig scene = test::repositoryScene(
      "quadruped_foot_drop_sand.json", {"contacts.model=" + test::mlpConfig(mlp).dump(), "duration=0.5"});
  const ContactModelRegistry models = ContactModelRegistry::withBuiltins();
  Simulation sim = buildSimulation(scene, models);
  const int nq = sim.model().nq;
  constexpr int kEntries = 4, kSteps = 8;
  RolloutRequest request;
  request.initial_states.resize(kEntries, 2 * nq);
  for (int b = 0; b < kEntries; ++b) {  // the scene's drop at four speeds
    Eigen::VectorXd qd = sim.initialVelocity();
    qd *= 0.5 + 0.25 * b;
    request.initial_states.row(b) << sim.initialConfiguration().transpose(), qd.transpose();
  }
  request.steps = kSteps;

  const StateLayout layout = stateLayout(sim.system());
  std::vector<double> loop;
  Eigen::VectorXd x;
  int converged = 0;
  for (int b = 0; b < kEntries; ++b) {
    const Eigen::VectorXd q = request.initial_states.row(b).head(nq).transpose();
    const Eigen::VectorXd qd = request.initial_states.row(b).tail(nq).transpose();
    sim.setState(initialState(sim.system(), sim.options(), q, qd, sim.dt()));
    flattenState(layout, sim.state(), x);
    loop.insert(loop.end(), x.data(), x.data() + x.size());
    for (int k = 0; k < kSteps; ++k) {
      ASSERT_TRUE(sim.step().converged) << "entry " << b << " step " << k;
      ++converged;
      flattenState(layout, sim.state(), x);
      loop.insert(loop.end(), x.data(), x.data() + x.size());
    }
  }
  for (const int threads : {1, 2}) {
    request.threads = threads;
    const RolloutResult result = rollout(scene, models, request);
    EXPECT_TRUE(sameBits(result.states, loop)) << threads << " threads";
  }
}

}  // namespace
}  // namespace nmdp
