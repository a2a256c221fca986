// Heightfield CSV files (terrain/heightfield.hpp): built as a scene's {"type": "heightfield"} terrain
// and queried, with derivatives, inside, on the border of and outside the grid.
#include "fuzz/fuzz_support.hpp"
#include "terrain/terrain_factory.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace nmdp;
  fuzz::Scratch& scratch = fuzz::Scratch::fresh();
  const std::string path = scratch.write("heights.csv", fuzz::asText(data, size));
  fuzz::acceptingInputErrors([&] {
    const std::unique_ptr<Terrain> terrain =
        makeTerrain({{"type", "heightfield"}, {"file", path}, {"spacing", 0.1}}, ConfigContext{"fuzz terrain", ""});
    TerrainQuery q;
    for (double x : {-1.0, 0.0, 0.05, 0.37, 1e6})
      for (double y : {-0.5, 0.0, 0.12, 1e6}) terrain->query(Vec3(x, y, 0.3), q, true);
  });
  return 0;
}
