#include "multibody/stl_mesh.hpp"

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <sstream>

#include "common/input_error.hpp"
#include "common/input_file.hpp"
#include "common/limits.hpp"

namespace nmdp {

namespace {

float readFloatLE(const unsigned char* p) {
  const uint32_t bits = static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) |
                        (static_cast<uint32_t>(p[2]) << 16) | (static_cast<uint32_t>(p[3]) << 24);
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

uint32_t readU32LE(const unsigned char* p) {
  return static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) | (static_cast<uint32_t>(p[2]) << 16) |
         (static_cast<uint32_t>(p[3]) << 24);
}

void parseBinary(const std::string& path, const std::string& bytes, StlMesh& mesh) {
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const uint32_t count = readU32LE(data + 80);
  mesh.binary = true;
  mesh.name = bytes.substr(0, 80);
  mesh.name = mesh.name.substr(0, mesh.name.find('\0'));
  while (!mesh.name.empty() && std::isspace(static_cast<unsigned char>(mesh.name.back()))) mesh.name.pop_back();
  mesh.vertices.reserve(3 * static_cast<size_t>(count));
  for (uint32_t t = 0; t < count; ++t) {
    const unsigned char* tri = data + 84 + 50 * static_cast<size_t>(t) + 12;  // skip the normal
    for (int k = 0; k < 3; ++k) {
      const unsigned char* v = tri + 12 * k;
      const Vec3 p(readFloatLE(v), readFloatLE(v + 4), readFloatLE(v + 8));
      if (!p.allFinite())
        throw InputError(path + ": binary STL triangle " + std::to_string(t) + " has a non-finite vertex");
      mesh.vertices.push_back(p);
    }
  }
}

void parseAscii(const std::string& path, const std::string& bytes, StlMesh& mesh) {
  std::istringstream in(bytes);
  std::string word;
  if (!(in >> word) || word != "solid") throw InputError(path + ": not an STL file (neither ASCII 'solid' nor binary)");
  std::string rest;
  std::getline(in, rest);
  const size_t b = rest.find_first_not_of(" \t\r");
  mesh.name = b == std::string::npos ? "" : rest.substr(b);
  while (!mesh.name.empty() && std::isspace(static_cast<unsigned char>(mesh.name.back()))) mesh.name.pop_back();
  mesh.binary = false;
  bool ended = false;
  while (in >> word) {
    if (word == "vertex") {
      Vec3 p;
      if (!(in >> p.x() >> p.y() >> p.z()) || !p.allFinite())
        throw InputError(path + ": ASCII STL vertex " + std::to_string(mesh.vertices.size()) + " is malformed");
      mesh.vertices.push_back(p);
    } else if (word == "endsolid") {
      ended = true;
      break;
    }
  }
  if (!ended) throw InputError(path + ": ASCII STL is truncated (no 'endsolid')");
  if (mesh.vertices.size() % 3 != 0)
    throw InputError(path + ": ASCII STL has " + std::to_string(mesh.vertices.size()) +
                     " vertices, not a multiple of 3");
}

}  // namespace

StlMesh readStl(const std::string& path) {
  const std::string bytes = readInputFile(path, "STL mesh file", limits::kMaxMeshFileBytes);
  StlMesh mesh;
  if (bytes.size() >= 84) {
    const uint32_t count = readU32LE(reinterpret_cast<const unsigned char*>(bytes.data()) + 80);
    if (bytes.size() == 84 + 50 * static_cast<uint64_t>(count)) {
      parseBinary(path, bytes, mesh);
      return mesh;
    }
  }
  const size_t first = bytes.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && bytes.compare(first, 5, "solid") == 0) {
    parseAscii(path, bytes, mesh);
    return mesh;
  }
  if (bytes.size() < 84) throw InputError(path + ": STL file is truncated (" + std::to_string(bytes.size()) + " bytes)");
  throw InputError(path + ": binary STL size does not match its triangle count (truncated or not an STL file)");
}

}  // namespace nmdp
