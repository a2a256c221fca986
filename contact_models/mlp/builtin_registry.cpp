// The registry of the built-in contact models. Defined here, in the one target that links libtorch,
// because the MLP is among them; the registry itself (contact_models/registry.cpp) needs no libtorch.
#include "contact_models/coulomb_model.hpp"
#include "contact_models/mlp/mlp_model.hpp"
#include "contact_models/rbf_model.hpp"
#include "contact_models/registry.hpp"

namespace nmdp {

ContactModelRegistry ContactModelRegistry::withBuiltins() {
  ContactModelRegistry r;
  r.add("coulomb", kCoulombParameters, makeCoulombModel);
  r.add("rbf", kRbfParameters, makeRbfModel);
  r.add("mlp", kMlpParameters, makeMlpModel);
  return r;
}

}  // namespace nmdp
