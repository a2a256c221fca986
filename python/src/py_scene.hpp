// nmdp.Scene: a scene file loaded with its overrides and checked (sim/scene.hpp), shared by the
// simulations and rollouts built from it. Immutable once loaded, so sharing needs no copy.
#pragma once
#include <memory>

#include "sim/scene.hpp"

namespace nmdp::python {

struct PyScene {
  std::shared_ptr<const SceneConfig> config;
};

}  // namespace nmdp::python
