// gen-rft configuration JSON (training/rft_config.hpp, and training/rft3d_config.hpp with
// "dimension": 3): parsed; its resolved form must parse to the
// same configuration (it is written beside the samples to regenerate them); samples are generated
// when the work is small enough for an input to take milliseconds.
#include <stdexcept>

#include "common/json_text.hpp"
#include "fuzz/fuzz_support.hpp"
#include "training/rft.hpp"
#include "training/rft3d_config.hpp"
#include "training/rft_config.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace nmdp;
  fuzz::acceptingInputErrors([&] {
    const nlohmann::json config = parseJson(fuzz::asText(data, size), "fuzz rft");
    if (isRft3dConfig(config, "fuzz rft")) {  // "dimension": 3
      const Rft3dConfig c = readRft3dConfig(config, "fuzz rft");
      const Rft3dConfig again = readRft3dConfig(nlohmann::json::parse(c.resolved.dump()), "resolved");
      if (again.resolved != c.resolved) throw std::logic_error("gen-rft's resolved 3-D configuration does not parse to itself");
      const double work = static_cast<double>(c.grid.depths.size() * c.grid.betas.size() * c.grid.gammas.size() *
                                              c.grid.directions.size()) * c.foot.elements * c.foot.elements;
      if (work <= 2e5) rft3dConfigSamples(c);
      return;
    }
    const RftConfig c = readRftConfig(config, "fuzz rft");
    const RftConfig again = readRftConfig(nlohmann::json::parse(c.resolved.dump()), "resolved");
    if (again.resolved != c.resolved) throw std::logic_error("gen-rft's resolved configuration does not parse to itself");
    const double work = static_cast<double>(c.grid.depths.size() * c.grid.angles.size() * c.grid.directions.size()) * c.foot.elements;
    if (work <= 2e5) rftSamples(c.medium, c.foot, c.grid);
  });
  return 0;
}
