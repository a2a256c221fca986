// The one interface every solver consumes (DESIGN.md §7). A contact model maps the state of a
// contact frame (a sphere fixed on a link, queried against the terrain) to the vertices of its
// wrench polytope, V ∈ R^{6×K}: world frame, rows [torque about the sphere centre; force].
// Optionally it also returns dV/dξ_i for the 6-D perturbation ξ = [δω; δp] of the contact frame
// (a world rotation about the sphere centre, then a world translation). The solver chains it to
// ∂V/∂θ_j = Σ_i dV/dξ_i J_c(i, j) with the spatial Jacobian of the sphere centre.
#pragma once
#include <array>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "multibody/spatial.hpp"
#include "terrain/terrain.hpp"

namespace nmdp {

enum class DerivativeSupport { Analytic, Autograd, None };
const char* derivativeSupportName(DerivativeSupport d);

// World state of one contact, built by the solver from the robot's kinematics.
struct ContactFrame {
  Vec3 position = Vec3::Zero();    // sphere centre (the point whose Jacobian the solver uses)
  double radius = 0.0;             // sphere radius; the force acts at its lowest point
  Vec3 leg_axis = Vec3::UnitZ();   // unit, from the foot up the leg (link-fixed: rotates with δω)
  Vec3 lateral = Vec3::UnitY();    // unit, normal of the leg's sagittal plane before projection
  bool lateral_rotates = true;     // false when the sagittal plane is fixed in the world (planar base)
};

// One input of a contact model at a contact (a column of ContactModel::features), for the output
// file and the viewer: "depth" in "m", "lean" in "rad", ...
struct ContactFeatureInfo {
  std::string name;
  std::string unit;
  std::string description;  // one line
};

struct ContactWrenches {
  Mat6X V;                   // 6×K
  std::array<Mat6X, 6> dV;   // dV/dξ_i, each 6×K (only when derivatives were requested)
  void resize(int K) {
    V.setZero(6, K);
    for (Mat6X& d : dV) d.setZero(6, K);
  }
};

class ContactModel {
 public:
  virtual ~ContactModel() = default;
  virtual int vertexCount() const = 0;
  virtual DerivativeSupport derivative() const = 0;
  virtual std::string describe() const = 0;  // type and parameters, one line
  // The JSON object this model was built from, complete: "type" and every parameter the type
  // accepts with the value in use (defaults filled in, paths as resolved), so that the registry
  // builds the same model from it again. Null for a model that was not built from a configuration
  // (or cannot say); the caller then has only the configuration it gave.
  virtual nlohmann::json configuration() const { return nullptr; }

  // Evaluates every contact of one step in one call (learned models batch them). `out` must hold
  // frames.size() entries resized to vertexCount(). Asking for derivatives of a model whose
  // derivative() is None throws std::logic_error naming the zeroth-order alternative.
  virtual void evaluate(const std::vector<ContactFrame>& frames, const Terrain& terrain,
                        std::vector<ContactWrenches>& out, bool with_derivatives) const = 0;

  // What the model reads at a contact, one column each: the first is always the signed depth
  // (m, negative below the surface) as the model measures it; models that read more (the granular
  // models' lean angles) add columns. Fixed for the model's lifetime.
  virtual std::vector<ContactFeatureInfo> featureInfo() const;
  // The features of each frame, a row each: `out` is frames.size() × featureInfo().size() (any
  // other shape throws std::logic_error). Never allocates. The default is the one column of the
  // sphere's signed distance φ(c) − r.
  virtual void features(const std::vector<ContactFrame>& frames, const Terrain& terrain,
                        Eigen::Ref<Eigen::MatrixXd> out) const;

 protected:
  // Throws std::logic_error naming `model` unless `out` is frames × columns (for features()).
  static void requireFeatureShape(const char* model, std::size_t frames, const Eigen::Ref<Eigen::MatrixXd>& out,
                                  Eigen::Index columns);
};

}  // namespace nmdp
