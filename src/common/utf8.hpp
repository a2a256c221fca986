// UTF-8 checks for text that reaches JSON or HDF5 output (names from a URDF, --set strings): a
// byte sequence that is not UTF-8 would make nlohmann::json's dump throw and h5py fail to decode.
#pragma once
#include <string>

namespace nmdp {

// Whether `text` is well-formed UTF-8 (no overlong forms, no surrogates, at most U+10FFFF).
bool isValidUtf8(const std::string& text);

}  // namespace nmdp
