// Force data in the CSV layout of granular/sand_samples (features.csv, wrench_samples.csv and
// scalars.txt, given as one input separated by lines "@@"): imported as `nmdp fit --data FOLDER` does,
// then fitted by an RBF when small enough to stay fast.
#include "fuzz/fuzz_fit.hpp"
#include "fuzz/fuzz_support.hpp"
#include "training/force_dataset.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace nmdp;
  fuzz::Scratch& scratch = fuzz::Scratch::fresh();
  scratch.writeParts(fuzz::asText(data, size), {"features.csv", "wrench_samples.csv", "scalars.txt"});
  fuzz::acceptingInputErrors([&] { fuzz::fitIfSmall(importSandSamplesCsv(scratch.dir()), FitConfig{}, scratch.dir()); });
  return 0;
}
