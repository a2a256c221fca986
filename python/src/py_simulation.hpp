// nmdp.Simulation's C++ side: one Simulation (sim/simulation.hpp) built from a Scene, with what
// the Python views need beside it. Held by pybind11 in a unique_ptr and never moved, so the state
// buffers the numpy views point into stay where they are for the object's life.
#pragma once
#include <atomic>
#include <optional>
#include <pybind11/numpy.h>
#include <stdexcept>

#include "multibody/data.hpp"
#include "py_scene.hpp"
#include "sim/simulation.hpp"
#include "sim/state_vector.hpp"

namespace nmdp::python {

struct PySimulation {
  explicit PySimulation(const PyScene& scene_);

  PyScene scene;
  Simulation sim;
  Data kinematics;                 // the contacts' forward kinematics, apart from the integrator's
  StateLayout layout;              // of get_state() / set_state()
  Eigen::VectorXd flat;            // get_state()'s buffer
  std::optional<StepStats> last;   // of the last step; none before the first
  std::atomic<bool> busy{false};   // step() runs without the GIL: a second thread must not enter
};

// Holds a simulation for one call that changes it; RuntimeError if another thread is stepping it
// (step() releases the GIL), instead of a data race.
class ExclusiveUse {
 public:
  explicit ExclusiveUse(PySimulation& s) : busy_(s.busy) {
    if (busy_.exchange(true)) throw std::runtime_error("this Simulation is being stepped by another thread");
  }
  ~ExclusiveUse() { busy_ = false; }
  ExclusiveUse(const ExclusiveUse&) = delete;
  ExclusiveUse& operator=(const ExclusiveUse&) = delete;

 private:
  std::atomic<bool>& busy_;
};

// A read-only numpy view of `size` doubles at `data`, keeping `owner` (the Python Simulation)
// alive as its base.
pybind11::array readOnlyView(const double* data, pybind11::ssize_t size, pybind11::handle owner);

// The methods of nmdp.Simulation kept in files of their own.
void bindContacts(pybind11::class_<PySimulation>& c);  // sim.contacts (simulation_contacts.cpp)
void bindState(pybind11::class_<PySimulation>& c);     // get_state, set_state, set_feedforward (simulation_state.cpp)

}  // namespace nmdp::python
