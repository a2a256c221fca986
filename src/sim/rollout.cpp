#include "sim/rollout.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <stdexcept>
#include <string>
#include <thread>

#include "common/limits.hpp"

namespace nmdp {

namespace {

// A count too large for an integer type, as a number a reader takes in ("1.45e+10").
std::string countText(double count) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", count);
  return text;
}

// The PD target of a control row, read in place from the request (a pointer moved before every
// step): the worker's simulation owns it, so no target source is allocated per step. Evaluates to
// the same numbers HeldPdTarget(position, velocity) would.
class ControlRowTarget final : public PdTargetSource {
 public:
  explicit ControlRowTarget(int nq) : nq_(nq) {}
  void point(const double* row) { row_ = row; }
  void evaluate(double, PdTarget& out) const override {
    out.position = Eigen::Map<const Eigen::VectorXd>(row_, nq_);
    out.velocity = Eigen::Map<const Eigen::VectorXd>(row_ + nq_, nq_);
  }

 private:
  int nq_;
  const double* row_ = nullptr;
};

// What the request's shapes mean, once checked.
struct Shape {
  StateLayout layout;
  Eigen::Index batch = 0;
  bool flat_states = false;  // rows are flat states (else (q, q̇) rows)
  int control_width = 0;     // 0 (the scene's gait), 2 nq or 3 nq
};

std::string at(const char* name, Eigen::Index row, Eigen::Index column) {
  return std::string("rollout: ") + name + "[" + std::to_string(row) + ", " + std::to_string(column) + "]";
}

void checkInitialStates(const RolloutRequest& request, const Shape& shape, SimulationState& scratch) {
  const Eigen::Index rows = request.initial_states.rows();
  for (Eigen::Index b = 0; b < rows; ++b) {
    const auto row = request.initial_states.row(b);
    if (shape.flat_states) {
      try {
        unflattenState(shape.layout, row.transpose(), scratch);
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument("rollout: initial_states row " + std::to_string(b) + ": " + e.what());
      }
      continue;
    }
    for (Eigen::Index j = 0; j < row.size(); ++j)
      if (!std::isfinite(row[j])) throw std::invalid_argument(at("initial_states", b, j) + " is not finite");
  }
}

// The control width from the columns (2 nq or 3 nq per step), every entry finite and the
// feed-forward zero on the base coordinates (Simulation::setFeedforward's checks, made up front).
int checkControls(const RolloutRequest& request, const Model& model, Eigen::Index batch) {
  const RowMajorMatrix& u = request.controls;
  if (u.size() == 0) return 0;
  const Eigen::Index nq = model.nq, steps = request.steps;
  if (u.rows() != batch || steps == 0 || (u.cols() != steps * 2 * nq && u.cols() != steps * 3 * nq))
    throw std::invalid_argument("rollout: controls is " + std::to_string(u.rows()) + " x " + std::to_string(u.cols()) +
                                ", expected " + std::to_string(batch) + " x " + std::to_string(steps * 2 * nq) +
                                " (steps · 2 nq: target position and velocity) or " + std::to_string(batch) + " x " +
                                std::to_string(steps * 3 * nq) + " (steps · 3 nq: and the feed-forward torque)");
  const Eigen::Index width = u.cols() / steps;
  for (Eigen::Index b = 0; b < u.rows(); ++b)
    for (Eigen::Index j = 0; j < u.cols(); ++j) {
      const double v = u(b, j);
      const Eigen::Index part = (j % width) / nq, coordinate = j % nq;
      const Body& body = model.bodies[static_cast<size_t>(coordinate)];
      const bool finite = std::isfinite(v), base_torque = part == 2 && body.is_base && v != 0.0;
      if (finite && !base_torque) continue;
      const char* what = part == 0 ? "target position" : part == 1 ? "target velocity" : "feed-forward torque";
      throw std::invalid_argument(at("controls", b, j) + " (step " + std::to_string(j / width) + ", " + what + " of " +
                                  body.joint_name + ") " +
                                  (finite ? "is nonzero on an unactuated base coordinate" : "is not finite"));
    }
  return static_cast<int>(width);
}

Shape checkRequest(const RolloutRequest& request, const Simulation& sim) {
  if (request.threads < 1 || request.threads > limits::kMaxRolloutThreads)
    throw std::invalid_argument("rollout: threads is " + std::to_string(request.threads) + ", expected 1 to " +
                                std::to_string(limits::kMaxRolloutThreads));
  if (request.steps < 0 || request.steps > limits::kMaxSteps)
    throw std::invalid_argument("rollout: steps is " + std::to_string(request.steps) + ", expected ≥ 0");
  Shape shape;
  shape.layout = stateLayout(sim.system());
  shape.batch = request.initial_states.rows();
  const Eigen::Index nx = shape.layout.size(), nq = shape.layout.nq, cols = request.initial_states.cols();
  if (cols != nx && cols != 2 * nq)
    throw std::invalid_argument("rollout: initial_states has " + std::to_string(cols) + " columns, expected " +
                                std::to_string(nx) + " (flat states) or " + std::to_string(2 * nq) + " (q and q̇)");
  shape.flat_states = cols == nx;
  const double entries = static_cast<double>(shape.batch) * (request.steps + 1.0) * static_cast<double>(nx);
  if (entries > static_cast<double>(limits::kMaxRolloutStateEntries))
    throw std::invalid_argument("rollout: the result would hold " + countText(entries) + " doubles (batch " +
                                std::to_string(shape.batch) + " x " + std::to_string(request.steps + 1) + " states x " +
                                std::to_string(nx) + "), more than " +
                                std::to_string(limits::kMaxRolloutStateEntries) + ": split the batch");
  SimulationState scratch = sim.state();
  checkInitialStates(request, shape, scratch);
  shape.control_width = checkControls(request, sim.model(), shape.batch);
  return shape;
}

// One thread's simulation and buffers, all made before the threads start.
struct Worker {
  Simulation sim;
  SimulationState start;
  Eigen::VectorXd flat;
  ControlRowTarget* target = nullptr;  // owned by sim, when there are controls
};

struct Batch {
  const RolloutRequest& request;
  const Shape& shape;
  RolloutResult& result;
  std::atomic<Eigen::Index> next{0};
  std::atomic<bool> stop{false};  // a worker threw: the others end after their entry
};

void runEntry(Worker& w, Batch& batch, Eigen::Index b) {
  const RolloutRequest& request = batch.request;
  const Shape& shape = batch.shape;
  const Eigen::Index nx = shape.layout.size(), nq = shape.layout.nq;
  const auto initial = request.initial_states.row(b);
  if (shape.flat_states) {
    unflattenState(shape.layout, initial.transpose(), w.start);
  } else {
    const Eigen::VectorXd q = initial.head(nq).transpose(), qd = initial.tail(nq).transpose();
    w.start = initialState(w.sim.system(), w.sim.options(), q, qd, w.sim.dt());
  }
  w.sim.setState(w.start);
  double* out = batch.result.states.data() + b * (request.steps + 1) * nx;
  flattenState(shape.layout, w.sim.state(), w.flat);
  std::copy(w.flat.data(), w.flat.data() + nx, out);
  StepStatus status = StepStatus::Converged;
  int done = 0;
  for (int k = 0; k < request.steps; ++k) {
    if (shape.control_width > 0) {
      const double* u = request.controls.row(b).data() + static_cast<Eigen::Index>(k) * shape.control_width;
      w.target->point(u);
      if (shape.control_width == 3 * nq) w.sim.setFeedforward(Eigen::Map<const Eigen::VectorXd>(u + 2 * nq, nq));
    }
    const StepStats stats = w.sim.step();
    out += nx;
    if (!stats.converged) {
      status = stats.status;
      std::fill(out, out + (request.steps - k) * nx, std::numeric_limits<double>::quiet_NaN());
      break;
    }
    flattenState(shape.layout, w.sim.state(), w.flat);
    std::copy(w.flat.data(), w.flat.data() + nx, out);
    ++done;
  }
  batch.result.status[static_cast<size_t>(b)] = status;
  batch.result.steps_done[static_cast<size_t>(b)] = done;
}

// Takes entries until none is left; an exception ends this worker and asks the others to stop.
void work(Worker& w, Batch& batch, std::exception_ptr& error) {
  try {
    for (;;) {
      if (batch.stop.load()) return;
      const Eigen::Index b = batch.next.fetch_add(1);
      if (b >= batch.shape.batch) return;
      runEntry(w, batch, b);
    }
  } catch (...) {
    error = std::current_exception();
    batch.stop.store(true);
  }
}

}  // namespace

RolloutResult rollout(const SceneConfig& scene, const ContactModelRegistry& models, const RolloutRequest& request) {
  std::vector<Worker> workers;
  workers.push_back({buildSimulation(scene, models), {}, {}, nullptr});
  const Shape shape = checkRequest(request, workers.front().sim);
  const Eigen::Index count = std::max<Eigen::Index>(1, std::min<Eigen::Index>(request.threads, shape.batch));
  while (static_cast<Eigen::Index>(workers.size()) < count)
    workers.push_back({buildSimulation(scene, models), {}, {}, nullptr});
  for (Worker& w : workers) {
    w.start = w.sim.state();
    w.flat.resize(shape.layout.size());
    if (shape.control_width == 0) continue;
    auto target = std::make_unique<ControlRowTarget>(shape.layout.nq);
    w.target = target.get();
    w.sim.setTargets(std::move(target));
  }
  RolloutResult result;
  result.states.resize(static_cast<size_t>(shape.batch * (request.steps + 1) * shape.layout.size()));
  result.status.assign(static_cast<size_t>(shape.batch), StepStatus::Converged);
  result.steps_done.assign(static_cast<size_t>(shape.batch), 0);
  Batch batch{request, shape, result};
  std::vector<std::exception_ptr> errors(workers.size());
  std::vector<std::thread> threads;
  threads.reserve(workers.size() - 1);
  try {
    for (size_t i = 1; i < workers.size(); ++i)
      threads.emplace_back(work, std::ref(workers[i]), std::ref(batch), std::ref(errors[i]));
  } catch (...) {  // no thread to be had: stop those started (a joinable thread must not be destroyed)
    batch.stop.store(true);
    for (std::thread& t : threads) t.join();
    throw;
  }
  work(workers.front(), batch, errors.front());  // the calling thread is worker 0
  for (std::thread& t : threads) t.join();
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
  return result;
}

}  // namespace nmdp
