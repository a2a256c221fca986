// The simulated system a time step is taken for: robot, contacts, contact model, terrain, gains.
#pragma once
#include <Eigen/Core>
#include <csignal>
#include <vector>

#include "config/integrator_options.hpp"
#include "contact_models/contact_model.hpp"
#include "control/stable_pd.hpp"
#include "multibody/model.hpp"
#include "solver/contact_kinematics.hpp"
#include "terrain/terrain.hpp"

namespace nmdp {

// What the contact term of ∂G/∂θ is built from in one evaluation of the residual.
enum class ContactDerivative { Model, FiniteDifference, Dropped };

// A request to stop that the integrator polls between sub-steps and between the outer iterations
// of a step (e.g. a flag set by a SIGINT handler): once it reads nonzero the step ends with
// StepStatus::Cancelled, the state at its last accepted sub-step. Null: never.
using CancelFlag = const volatile std::sig_atomic_t*;

// The simulated system: robot, contacts, contact model, terrain and joint gains. Referenced, not
// owned; everything must outlive the workspaces built from it.
struct System {
  const Model* model = nullptr;
  std::vector<ContactPoint> contacts;
  const ContactModel* contact_model = nullptr;  // may be null when there are no contacts
  const Terrain* terrain = nullptr;             // may be null when there are no contacts
  PdGains gains;                                // sized nq (zero gains: a passive robot)
  // Constant generalized force added to the actuation (e.g. a push on the base), sized nq or empty.
  Eigen::VectorXd external_force;
};

// A robot on `terrain` touching it through `contact_model` at its detected feet (footContactPoints),
// driven by `gains`: the system most tests and benchmarks step.
System systemOnFeet(const Model& model, const ContactModel& contact_model, const Terrain& terrain, PdGains gains);

// Throws std::invalid_argument naming the problem: sizes, missing contact model or terrain, or a
// first-order method with a contact model that has no derivative (suggesting the zeroth-order twin).
void validateSystem(const System& system, const IntegratorOptions& options);

}  // namespace nmdp
