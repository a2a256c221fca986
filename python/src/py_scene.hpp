// nmdp.Scene: a scene file loaded with its overrides and checked (sim/scene.hpp), shared by the
// simulations and rollouts built from it. Immutable once loaded, so sharing needs no copy.
#pragma once
#include <memory>

#include "sim/scene.hpp"
#include "sim/simulation.hpp"

namespace nmdp::python {

struct PyScene {
  std::shared_ptr<const SceneConfig> config;
  // The robot's coordinate count, once known (a Simulation built from the scene, or a rollout's
  // shape check, tells it): -1 until then. Shared by the copies; read and written under the GIL.
  std::shared_ptr<int> known_nq = std::make_shared<int>(-1);

  int nq() const {  // loads the robot the first time (its errors as Simulation(scene) raises them)
    if (*known_nq < 0) *known_nq = loadSceneRobot(*config).nq;
    return *known_nq;
  }
};

}  // namespace nmdp::python
