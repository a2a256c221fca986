// URDF text (nmdp inspect, robot.urdf of a scene): load with each base type, then find the feet and
// describe the model as `nmdp inspect` does.
#include "fuzz/fuzz_support.hpp"
#include "multibody/feet.hpp"
#include "multibody/urdf_loader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace nmdp;
  fuzz::Scratch& scratch = fuzz::Scratch::fresh();
  const std::string path = scratch.write("robot.urdf", fuzz::asText(data, size));
  for (BaseType base : {BaseType::Floating, BaseType::Fixed}) {
    fuzz::acceptingInputErrors([&] {
      UrdfOptions options;
      options.base = base;
      const Model model = loadUrdf(path, options);
      detectFeet(model);
    });
  }
  return 0;
}
