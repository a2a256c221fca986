// The page nmdp view writes (the contract with the front end: viewer/README.md and the payload
// layout in view_payload.hpp): one self-contained HTML file holding the payload as JSON and the
// viewer's script, both inlined so that nothing else is needed to open it.
#pragma once
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace nmdp::app {

// The marker that makes a page recognisable as nmdp's output (io/output_path.hpp), so that a later
// `nmdp view` may replace it and nothing else.
inline constexpr const char* kViewPageMarker = "<meta name=\"nmdp-output\" content=\"view\">";

std::string base64(const void* bytes, size_t size);

// Payload arrays: {"dtype", "shape", "b64" of the little-endian bytes in C order}.
nlohmann::json floatArray(const std::vector<float>& values, const std::vector<size_t>& shape);
nlohmann::json doubleArray(const std::vector<double>& values, const std::vector<size_t>& shape);
nlohmann::json byteArray(const std::vector<std::uint8_t>& values, const std::vector<size_t>& shape);

// The viewer's script: $NMDP_VIEWER_BUNDLE, else the bundle of the source tree this nmdp was built
// from, else <folder of the executable>/../share/nmdp/nmdp-view.js. InputError naming the paths
// tried and how to build it when none exists.
std::string findViewerBundle();

// The HTML page: the payload (every '<' written \u003c, so no string can end its element) and the
// script (every "</script" written "<\/script").
std::string viewPage(const nlohmann::json& payload, const std::string& script);

}  // namespace nmdp::app
