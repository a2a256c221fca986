// HDF5 contact-model files (RBF and MLP, contact_models/rbf_function.hpp and mlp_function.hpp), as
// the text of fuzz/h5_text.hpp: written to a file, then loaded as {"type": "rbf"|"mlp", "file": ...}
// and evaluated.
#include "fuzz/fuzz_support.hpp"
#include "fuzz/h5_text.hpp"
#include "fuzz/model_probe.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace nmdp;
  fuzz::Scratch& scratch = fuzz::Scratch::fresh();
  const std::string path = scratch.write("model.h5", "");
  fuzz::writeHdf5FromText(fuzz::asText(data, size), path);
  for (const char* type : {"rbf", "mlp"})
    fuzz::acceptingInputErrors([&] { fuzz::probeContactModel({{"type", type}, {"file", path}}); });
  return 0;
}
