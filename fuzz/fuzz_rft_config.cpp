// gen-rft configuration JSON (training/rft_config.hpp): parsed; its resolved form must parse to the
// same configuration (it is written beside the samples to regenerate them); samples are generated
// when the work is small enough for an input to take milliseconds.
#include <stdexcept>

#include "common/json_text.hpp"
#include "fuzz/fuzz_support.hpp"
#include "training/rft.hpp"
#include "training/rft_config.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace nmdp;
  fuzz::acceptingInputErrors([&] {
    const RftConfig c = readRftConfig(parseJson(fuzz::asText(data, size), "fuzz rft"), "fuzz rft");
    const RftConfig again = readRftConfig(nlohmann::json::parse(c.resolved.dump()), "resolved");
    if (again.resolved != c.resolved) throw std::logic_error("gen-rft's resolved configuration does not parse to itself");
    const double work = static_cast<double>(c.grid.depths.size() * c.grid.angles.size() * c.grid.directions.size()) * c.foot.elements;
    if (work <= 2e5) rftSamples(c.medium, c.foot, c.grid);
  });
  return 0;
}
