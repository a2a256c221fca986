// The one way to build and step a simulation from a scene (sim/scene.hpp): `nmdp simulate`, the
// benchmarks, the fuzz target and the tests all build their runs with buildSimulation().
//
//   SceneConfig scene = parseScene(loadSceneJson(path), path);
//   Simulation sim = buildSimulation(scene, ContactModelRegistry::withBuiltins());
//   sim.addObserver([](const Simulation& s, const StepStats& stats) { ... });  // e.g. a writer
//   for (long i = 0; i < sim.scheduledSteps(); ++i)
//     if (!sim.step().converged) break;
//
// The contact-model registry is passed in so that this library does not link libtorch: callers
// that want the MLP pass ContactModelRegistry::withBuiltins() from nmdp_mlp, others a registry of
// their own (e.g. Coulomb only).
//
// A Simulation owns everything a run needs (robot, contact model, terrain, PD target source,
// system, integrator options, state, step workspace). It is movable (its parts live on the heap, so
// the references between them survive a move; a moved-from Simulation may only be assigned to or
// destroyed), holds no global state and, once warmed up, a step allocates nothing
// (tests/sim/test_simulation.cpp).
#pragma once
#include <Eigen/Core>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <vector>

#include "contact_models/registry.hpp"
#include "sim/scene.hpp"
#include "solver/integrator.hpp"

namespace nmdp {

class Simulation {
 public:
  // Called after every step that converged, in the order added, with the step's statistics. A step
  // that does not converge (failed, diverged, cancelled) is not observed: step() returns its
  // statistics and the state is where the integrator left it (its last accepted sub-step).
  using Observer = std::function<void(const Simulation&, const StepStats&)>;

  Simulation(Simulation&&) noexcept;
  Simulation& operator=(Simulation&&) noexcept;
  ~Simulation();

  // One output step of dt (integrator.dt), as `nmdp simulate` takes it; `cancel` (may be null) is
  // polled during the step (solver/integrator.hpp), which then ends with StepStatus::Cancelled.
  StepStats step(CancelFlag cancel = nullptr);
  void addObserver(Observer observer);

  double time() const;                   // s
  double dt() const;                     // integrator.dt, s
  long scheduledSteps() const;           // steps of dt the scene's duration takes (at least 1)
  const SimulationState& state() const;  // q, q̇ (nq, in the chart state().base_chart), time, ...
  // Replaces the state (e.g. one kept from state() earlier, or one unflattened from
  // sim/state_vector.hpp); std::invalid_argument if its sizes do not match the robot and its
  // contacts. Everything a step carries to the next is in the state (the QP's warm start included),
  // so the steps that follow depend on `state` alone: setState(state()) changes nothing, and a run
  // restored from a state kept at step k repeats the uninterrupted run from step k bit for bit, in
  // this simulation or another built from the same scene. The state's vectors keep their buffers
  // (they are copied into, here and by every step): a pointer to state().q stays valid for the
  // Simulation's life. contactWrenches() reads zero until the next step.
  void setState(const SimulationState& state);
  // The world pose of the trunk at the current state: position (m) and ZYX roll-pitch-yaw (rad), as
  // /base/position and /base/rpy of the output.
  void basePose(Vec3& position, Vec3& rpy) const;
  // [torque about the sphere centre; force] (world) per contact, of the last step (zero before the
  // first), averaged over its sub-steps by their duration.
  const std::vector<Vec6>& contactWrenches() const;

  const PdTargetSource& targets() const;
  void setTargets(std::unique_ptr<PdTargetSource> targets);  // from the next step on; not null
  // The feed-forward torque τ_ff (nq, N·m or N) of the PD law from the next step on, in place of the
  // scene's controller.tau_ff. std::invalid_argument naming the entry if its size is not nq, an entry
  // is not finite, or a base coordinate's entry is not 0 (the base is unactuated).
  void setFeedforward(const Eigen::Ref<const Eigen::VectorXd>& tau);

  const SceneConfig& scene() const;
  // The scene with every default filled in, the robot's included, and the contact model's own
  // account of its parameters: what `nmdp simulate` stores as the output's `config` attribute.
  const nlohmann::json& resolvedScene() const;
  const Model& model() const;
  const System& system() const;  // robot, contact points, contact model, terrain, gains
  const ContactModel& contactModel() const;
  const Terrain& terrain() const;
  const IntegratorOptions& options() const;
  const Eigen::VectorXd& initialConfiguration() const;  // q at t = 0 (nq)
  const Eigen::VectorXd& initialVelocity() const;       // q̇ at t = 0 (nq)
  const StepWorkspace& workspace() const;               // the last step's sub-step sizes, ...

 private:
  struct Parts;
  explicit Simulation(std::unique_ptr<Parts> parts);
  friend Simulation buildSimulation(const SceneConfig&, Model, const ContactModelRegistry&);
  std::unique_ptr<Parts> parts_;
};

// The robot of a scene: its URDF loaded as the scene says and every check that needs the robot
// (validateAgainstModel). InputError naming the scene key.
Model loadSceneRobot(const SceneConfig& scene);

// Builds the run the scene describes: contact model (from `models`), terrain, contact points, gains,
// gait and start state, checked as `nmdp simulate` checks them. Every error is an InputError
// "<scene file>: <key.path>: <what is wrong>" (the CLI's messages).
Simulation buildSimulation(const SceneConfig& scene, const ContactModelRegistry& models);
// The same with the robot already loaded by loadSceneRobot (a caller that polls for interruption
// between the two phases, as `nmdp simulate` does).
Simulation buildSimulation(const SceneConfig& scene, Model robot, const ContactModelRegistry& models);

}  // namespace nmdp
