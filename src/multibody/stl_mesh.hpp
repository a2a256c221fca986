// A minimal STL reader (binary and ASCII), used to fit contact spheres to mesh feet.
#pragma once
#include <string>
#include <vector>

#include "multibody/spatial.hpp"

namespace nmdp {

struct StlMesh {
  std::string name;               // the "solid" name (ASCII) or the 80-byte header text (binary)
  std::vector<Vec3> vertices;     // 3 per triangle, in file units (no deduplication)
  bool binary = false;
  int triangleCount() const { return static_cast<int>(vertices.size() / 3); }
};

// Reads an STL file. Binary files are recognised by their size (84 + 50 · triangle count bytes),
// not by the header, since many binary files (e.g. Solo-12's) also begin with "solid".
// Throws InputError naming the file when it cannot be opened, is truncated, or is malformed.
StlMesh readStl(const std::string& path);

}  // namespace nmdp
