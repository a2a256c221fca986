// HDF5 force datasets (training/force_dataset.hpp), as the text of fuzz/h5_text.hpp: read, grouped by
// point, augmented as `nmdp fit` does by default, and fitted by an RBF when small enough to stay fast.
#include "fuzz/fuzz_fit.hpp"
#include "fuzz/fuzz_support.hpp"
#include "fuzz/h5_text.hpp"
#include "training/force_dataset.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace nmdp;
  fuzz::Scratch& scratch = fuzz::Scratch::fresh();
  const std::string path = scratch.write("data.h5", "");
  fuzz::writeHdf5FromText(fuzz::asText(data, size), path);
  fuzz::acceptingInputErrors([&] { fuzz::fitIfSmall(readForceDataset(path), FitConfig{}, path); });
  return 0;
}
