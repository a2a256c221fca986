// `nmdp fit` configuration JSON (training/fit_config.hpp): parsed; the settings it records in a model
// file must parse to the same settings; with them an RBF is fitted to the project's RFT sand samples.
#include <stdexcept>

#include "common/json_text.hpp"
#include "fuzz/fuzz_fit.hpp"
#include "fuzz/fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace nmdp;
  static const ForceDataset samples = importSandSamplesCsv(fuzz::sourcePath("data/granular/rft_quadruped_samples"));
  fuzz::acceptingInputErrors([&] {
    const FitConfig config = parseFitConfig(parseJson(fuzz::asText(data, size), "fuzz fit"), ConfigContext{"fuzz fit", ""});
    for (const char* model : {"rbf", "mlp"}) {
      const nlohmann::ordered_json recorded = fitConfigJson(config, 0.05, model);
      const FitConfig again = parseFitConfig(nlohmann::json::parse(recorded.dump()), ConfigContext{"recorded", ""});
      if (fitConfigJson(again, 0.05, model) != recorded) throw std::logic_error("the recorded fit settings do not parse to themselves");
    }
    fuzz::fitIfSmall(samples, config, "rft_quadruped_samples");
  });
  return 0;
}
