// The published RBF text format (granular/robosimian_sand_rbf): inputs.txt and weights.txt, given as
// one input with the two files separated by a line "@@", loaded as {"type": "rbf", "file": FOLDER}
// and evaluated.
#include "fuzz/fuzz_support.hpp"
#include "fuzz/model_probe.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace nmdp;
  fuzz::Scratch& scratch = fuzz::Scratch::fresh();
  scratch.writeParts(fuzz::asText(data, size), {"inputs.txt", "weights.txt"});
  fuzz::acceptingInputErrors([&] { fuzz::probeContactModel({{"type", "rbf"}, {"file", scratch.dir()}, {"format", "published"}}); });
  return 0;
}
