// STL meshes (binary or ASCII), read for foot detection when a URDF's collision geometry is a mesh.
#include "fuzz/fuzz_support.hpp"
#include "multibody/stl_mesh.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace nmdp;
  fuzz::Scratch& scratch = fuzz::Scratch::fresh();
  const std::string path = scratch.write("foot.stl", fuzz::asText(data, size));
  fuzz::acceptingInputErrors([&] { readStl(path); });
  return 0;
}
