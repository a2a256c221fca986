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

// What a vertex of the network's output is (attribute 'wrench' of the model file): a planar
// wrench (F_x, F_z, τ_y) of the features (φ, β), or a spatial one (τ_x, τ_y, τ_z, F_x, F_y, F_z) of
// (φ, β, γ) (contact_models/spatial_wrench_model.hpp).
enum class MlpWrench { Planar, Spatial };
inline constexpr EnumName<MlpWrench> kMlpWrenches[] = {{MlpWrench::Planar, "planar"}, {MlpWrench::Spatial, "spatial"}};
// The network's inputs: 2 (φ, β) or 3 (φ, β, γ).
inline constexpr int mlpFeatureCount(MlpWrench wrench) { return wrench == MlpWrench::Spatial ? 3 : 2; }
// Outputs per vertex: 3 (F_x, F_z, τ_y) or 6 (τ_x, τ_y, τ_z, F_x, F_y, F_z).
inline constexpr int mlpWrenchWidth(MlpWrench wrench) { return wrench == MlpWrench::Spatial ? 6 : 3; }

}  // namespace nmdp
