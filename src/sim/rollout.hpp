// Many independent runs of one scene from given states, on a pool of threads: the batch
// simulation behind nmdp.rollout in Python (reinforcement learning, system identification,
// sampling-based control).
//
// Each thread owns one Simulation built from the scene (before the threads start: building reads
// files) and takes entries from a shared counter; every entry starts from its state with setState,
// and a step depends on the state alone (sim/simulation.hpp), so an entry's result does not depend
// on which thread ran it or what it ran before: 1 thread and k threads give the same bits, and an
// entry gives the bits of a loop of Simulation::step from the same state (with setTargets(
// HeldPdTarget(...)) and setFeedforward before each step, for controls).
//
// libtorch (the MLP contact model) runs its operations on the calling thread: MlpFunction sets its
// intra-op threads to 1 (process-wide), so k rollout threads use k cores and each thread evaluates
// its own simulation's model.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "sim/simulation.hpp"
#include "sim/state_vector.hpp"

namespace nmdp {

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

struct RolloutRequest {
  // One flat state (sim/state_vector.hpp) per row, [B, layout.size()]; or rows of (q, q̇), [B, 2 nq],
  // each started as the scene's own start state is (initialState at time 0).
  RowMajorMatrix initial_states;
  int steps = 0;  // steps of the scene's dt per entry
  // Empty (the scene's gait), or [B, steps · width] with width 2 nq (PD target position and
  // velocity, held over the step) or 3 nq (and the feed-forward torque).
  RowMajorMatrix controls;
  int threads = 1;
};

struct RolloutResult {
  // [B, (steps + 1) · layout.size()] row-major: the flat state after every step, the start first.
  // From a step that does not converge on, that entry's states are NaN (its row included).
  std::vector<double> states;
  std::vector<StepStatus> status;  // per entry: Converged, or the status of the step that failed
  std::vector<int> steps_done;     // per entry: the steps that converged
};

// Builds one simulation per thread from `scene` and runs every entry. std::invalid_argument naming
// the argument for a wrong shape, a non-finite entry or threads < 1 (checked before any run).
RolloutResult rollout(const SceneConfig& scene, const ContactModelRegistry& models, const RolloutRequest& request);

}  // namespace nmdp
