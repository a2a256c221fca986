// The names of the MLP contact model's choices, as model files and fit configurations write them:
// one EnumName table per enum (common/named_enum.hpp). No libtorch: the fit configuration, in the
// core libraries, parses them too.
#pragma once
#include "common/named_enum.hpp"

namespace nmdp {

enum class MlpActivation { Tanh, Softplus, Silu };
inline constexpr EnumName<MlpActivation> kMlpActivations[] = {
    {MlpActivation::Tanh, "tanh"}, {MlpActivation::Softplus, "softplus"}, {MlpActivation::Silu, "silu"}};

// What multiplies the network's output N (mlp_function.hpp).
enum class MlpOutputEnvelope {
  None,       // W = N
  Depth,      // W = (−φ) ⊙ N: zero at the surface
  SoftDepth,  // W = w softplus(−φ/w) ⊙ N: −φ below the surface, w log 2 at it, fading above it
};
inline constexpr EnumName<MlpOutputEnvelope> kMlpOutputEnvelopes[] = {
    {MlpOutputEnvelope::None, "none"}, {MlpOutputEnvelope::Depth, "depth"}, {MlpOutputEnvelope::SoftDepth, "soft_depth"}};

}  // namespace nmdp
