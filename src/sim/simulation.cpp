#include "sim/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "common/input_error.hpp"
#include "multibody/kinematics.hpp"
#include "multibody/urdf_loader.hpp"
#include "common/limits.hpp"
#include "contact_models/patched_model.hpp"
#include "terrain/material_config.hpp"
#include "terrain/terrain_factory.hpp"

namespace nmdp {

struct Simulation::Parts {
  Parts(const SceneConfig& scene_config, Model robot) : scene(scene_config), model(std::move(robot)), pose_data(model) {}

  SceneConfig scene;
  Model model;
  std::unique_ptr<ContactModel> contact_model;
  std::unique_ptr<Terrain> terrain;
  std::unique_ptr<PdTargetSource> targets;
  System system;  // refers to the parts above
  Eigen::VectorXd q0, qd0;
  std::unique_ptr<StepWorkspace> workspace;
  SimulationState state;
  nlohmann::json resolved;
  std::vector<Observer> observers;
  Data pose_data;  // basePose's and trunkState's kinematics, apart from the integrator's
  TrunkState trunk_start;  // the trunk at t = 0: the heading and line a trot's feedback holds
};

namespace {

// Library builders report unusable values with std::invalid_argument; here they become input
// errors naming the scene (and the key, where one is to blame).
template <class F>
auto asInputError(const std::string& where, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const std::invalid_argument& e) {
    throw InputError(where + ": " + e.what());
  }
}

// The trunk's yaw and horizontal position for a floating base (zero otherwise).
TrunkState trunkState(const Model& model, Data& data, const Mat3& chart, const Eigen::VectorXd& q) {
  TrunkState trunk;
  if (model.base != BaseType::Floating) return trunk;
  data.base_chart = chart;
  forwardKinematics(model, data, q);
  Vec3 position, rpy;
  basePose(model, data, position, rpy);
  trunk.yaw = rpy.z();
  trunk.position = position.head<2>();
  return trunk;
}

// The scene's contact model over ground of several materials: the default (contacts.model) and
// each material's model, blended (contact_models/patched_model.hpp); the default alone otherwise.
std::unique_ptr<ContactModel> withMaterials(std::unique_ptr<ContactModel> default_model, const TerrainMaterials& materials,
                                            const ContactModelRegistry& models, const ConfigContext& terrain_ctx) {
  if (!materials.layout) return default_model;
  std::vector<std::unique_ptr<ContactModel>> parts;
  parts.push_back(std::move(default_model));
  for (size_t m = 0; m < materials.models.size(); ++m)
    parts.push_back(models.build(materials.models[m], ConfigContext{terrain_ctx.where + "." + materials.model_keys[m], terrain_ctx.base_dir}));
  int vertices = 0;
  for (const auto& part : parts) vertices += part->vertexCount();
  if (vertices > limits::kMaxVertices)
    throw InputError(terrain_ctx.where + ": the materials' models have " + std::to_string(vertices) +
                     " vertices together, more than the " + std::to_string(limits::kMaxVertices) + " a contact may have");
  return std::make_unique<PatchedModel>(materials.layout, std::move(parts));
}

}  // namespace

Model loadSceneRobot(const SceneConfig& scene) {
  Model model = loadUrdf(scene.urdf, urdfOptionsFor(scene));
  validateAgainstModel(scene, model);
  return model;
}

Simulation buildSimulation(const SceneConfig& scene, const ContactModelRegistry& models) {
  return buildSimulation(scene, loadSceneRobot(scene), models);
}

Simulation buildSimulation(const SceneConfig& scene, Model robot, const ContactModelRegistry& models) {
  auto p = std::make_unique<Simulation::Parts>(scene, std::move(robot));
  const SceneConfig& config = p->scene;
  p->contact_model = models.build(config.contact_model, ConfigContext{config.path + ": contacts.model", config.base_dir});
  const ConfigContext terrain_ctx{config.path + ": terrain", config.base_dir};
  p->terrain = makeTerrain(config.terrain, terrain_ctx);
  p->contact_model = withMaterials(std::move(p->contact_model), makeTerrainMaterials(config.terrain, *p->terrain, terrain_ctx),
                                   models, terrain_ctx);
  p->system.model = &p->model;
  p->system.contacts = contactPointsFor(config, p->model);
  p->system.contact_model = p->contact_model.get();
  p->system.terrain = p->terrain.get();
  p->system.gains = gainsFor(config, p->model);
  p->targets = asInputError(config.path + ": controller.gait", [&] { return gaitFor(config, p->model); });
  asInputError(config.path, [&] { validateSystem(p->system, config.integrator); });
  p->q0 = initialConfiguration(config, p->model);
  p->qd0 = initialVelocity(config, p->model);
  p->workspace = std::make_unique<StepWorkspace>(p->system, config.integrator);
  p->state = initialState(p->system, config.integrator, p->q0, p->qd0, config.dt);
  p->trunk_start = trunkState(p->model, p->pose_data, p->state.base_chart, p->state.q);
  p->resolved = resolvedWithModel(config, p->model);
  // The model's own account of its parameters lists the defaults it filled in, not only the keys given.
  if (nlohmann::json used = p->contact_model->configuration(); !used.is_null()) p->resolved["contacts"]["model"] = std::move(used);
  return Simulation(std::move(p));
}

Simulation::Simulation(std::unique_ptr<Parts> parts) : parts_(std::move(parts)) {}
Simulation::Simulation(Simulation&&) noexcept = default;
Simulation& Simulation::operator=(Simulation&&) noexcept = default;
Simulation::~Simulation() = default;

StepStats Simulation::step(CancelFlag cancel) {
  Parts& p = *parts_;
  if (p.targets->observesTrunk())
    p.targets->observeTrunk(p.trunk_start, trunkState(p.model, p.pose_data, p.state.base_chart, p.state.q));
  const StepStats stats = advance(p.system, p.scene.integrator, *p.targets, p.state, p.scene.dt, *p.workspace, cancel);
  if (stats.converged)
    for (const Observer& observer : p.observers) observer(*this, stats);
  return stats;
}

void Simulation::addObserver(Observer observer) { parts_->observers.push_back(std::move(observer)); }

double Simulation::time() const { return parts_->state.time; }
double Simulation::dt() const { return parts_->scene.dt; }
long Simulation::scheduledSteps() const { return std::max(1L, std::lround(parts_->scene.duration / parts_->scene.dt)); }
const SimulationState& Simulation::state() const { return parts_->state; }

void Simulation::setState(const SimulationState& state) {
  Parts& p = *parts_;
  const Eigen::Index n = p.model.nq;
  const size_t contacts = p.system.contacts.size();
  const size_t weights = static_cast<size_t>(p.state.w.size());
  if (state.q.size() != n || state.qd.size() != n || state.q_prev.size() != n || state.qd_prev.size() != n ||
      state.contact_active.size() != contacts || static_cast<size_t>(state.w.size()) != weights ||
      state.qp_warm.at_bound.size() != weights || state.qp_warm.cap.size() != contacts)
    throw std::invalid_argument("Simulation::setState: expected q, q̇, q_prev and q̇_prev of size " + std::to_string(n) +
                                ", contact_active and qp_warm.cap of size " + std::to_string(contacts) +
                                ", w and qp_warm.at_bound of size " + std::to_string(weights));
  p.state = state;  // same sizes: every vector keeps its buffer
  // The workspace carries nothing into the next step (the QP's warm start is in the state, the
  // energy check's cache is keyed by q, q̇ and the chart); only the last step's outputs are reset.
  for (Vec6& wrench : p.workspace->contact_wrench) wrench.setZero();
  p.workspace->substep_sizes.clear();
  p.workspace->substep_in_contact.clear();
}

void Simulation::basePose(Vec3& position, Vec3& rpy) const {
  Parts& p = *parts_;
  p.pose_data.base_chart = p.state.base_chart;
  forwardKinematics(p.model, p.pose_data, p.state.q);
  nmdp::basePose(p.model, p.pose_data, position, rpy);
}

const std::vector<Vec6>& Simulation::contactWrenches() const { return parts_->workspace->contact_wrench; }

const PdTargetSource& Simulation::targets() const { return *parts_->targets; }

void Simulation::setTargets(std::unique_ptr<PdTargetSource> targets) {
  if (!targets) throw std::invalid_argument("Simulation::setTargets: no target source");
  parts_->targets = std::move(targets);
}

void Simulation::setFeedforward(const Eigen::Ref<const Eigen::VectorXd>& tau) {
  Parts& p = *parts_;
  const Eigen::Index n = p.model.nq;
  if (tau.size() != n)
    throw std::invalid_argument("Simulation::setFeedforward: tau has " + std::to_string(tau.size()) +
                                " entries, expected nq = " + std::to_string(n));
  for (Eigen::Index j = 0; j < n; ++j) {
    const Body& body = p.model.bodies[static_cast<size_t>(j)];
    const bool finite = std::isfinite(tau[j]);
    if (finite && !(body.is_base && tau[j] != 0.0)) continue;  // no message built: called at every control step
    throw std::invalid_argument("Simulation::setFeedforward: tau[" + std::to_string(j) + "] (" + body.joint_name + ") " +
                                (finite ? "is nonzero on an unactuated base coordinate" : "is not finite"));
  }
  // The integrator reads the gains from the system at every evaluation (residual, energy check).
  p.system.gains.tau_ff = tau;
}

const SceneConfig& Simulation::scene() const { return parts_->scene; }
const nlohmann::json& Simulation::resolvedScene() const { return parts_->resolved; }
const Model& Simulation::model() const { return parts_->model; }
const System& Simulation::system() const { return parts_->system; }
const ContactModel& Simulation::contactModel() const { return *parts_->contact_model; }
const Terrain& Simulation::terrain() const { return *parts_->terrain; }
const IntegratorOptions& Simulation::options() const { return parts_->scene.integrator; }
const Eigen::VectorXd& Simulation::initialConfiguration() const { return parts_->q0; }
const Eigen::VectorXd& Simulation::initialVelocity() const { return parts_->qd0; }
const StepWorkspace& Simulation::workspace() const { return *parts_->workspace; }

}  // namespace nmdp
