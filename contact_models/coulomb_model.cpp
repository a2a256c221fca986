#include "contact_models/coulomb_model.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "common/input_error.hpp"
#include "common/json_text.hpp"
#include "common/limits.hpp"

namespace nmdp {

void tangentBasis(const Vec3& n, Vec3& t1, Vec3& t2, Mat3* dt1, Mat3* dt2) {
  const double x = n.x(), y = n.y(), z = n.z();
  // σ = +1: the smallest rotation z → n applied to (x, y); σ = −1: the smallest rotation −z → n
  // applied to (x, −y) (Duff et al. 2017, "Building an orthonormal basis, revisited"). With
  // a = 1/(1 + σ z):   t₁ = (1 − a x², −a x y, −σ x),   t₂ = (−σ a x y, σ (1 − a y²), −y).
  const double s = z > -0.5 ? 1.0 : -1.0;
  const double a = 1.0 / (1.0 + s * z);
  t1 = Vec3(1.0 - a * x * x, -a * x * y, -s * x);
  t2 = Vec3(-s * a * x * y, s * (1.0 - a * y * y), -y);
  if (!dt1 && !dt2) return;
  const double da_dz = -s * a * a;
  // Columns: ∂/∂x, ∂/∂y, ∂/∂z.
  if (dt1) {
    *dt1 << -2.0 * a * x, 0.0, -x * x * da_dz,
            -a * y, -a * x, -x * y * da_dz,
            -s, 0.0, 0.0;
  }
  if (dt2) {
    *dt2 << -s * a * y, -s * a * x, -s * x * y * da_dz,
            0.0, -2.0 * s * a * y, -s * y * y * da_dz,
            0.0, -1.0, 0.0;
  }
}

CoulombModel::CoulombModel(const CoulombParameters& params) : params_(params) {
  if (!(params_.mu > 0.0) || !std::isfinite(params_.mu)) throw std::invalid_argument("coulomb model: mu must be > 0");
  if (params_.K < 3) throw std::invalid_argument("coulomb model: K must be at least 3");
  if (!(params_.k > 0.0) || !std::isfinite(params_.k)) throw std::invalid_argument("coulomb model: k must be > 0");
  if (!(params_.p >= 2.0) || !std::isfinite(params_.p)) throw std::invalid_argument("coulomb model: p must be >= 2");
  if (!(params_.zeta > 0.0) || !std::isfinite(params_.zeta))
    throw std::invalid_argument("coulomb model: zeta must be > 0");
  cos_.resize(params_.K);
  sin_.resize(params_.K);
  for (int i = 0; i < params_.K; ++i) {
    const double phi = 2.0 * M_PI * i / params_.K;
    cos_[i] = std::cos(phi);
    sin_[i] = std::sin(phi);
  }
}

std::string CoulombModel::describe() const {
  std::ostringstream s;
  s << "coulomb: mu " << params_.mu << ", K " << params_.K << ", k " << params_.k << " N/m^" << params_.p << ", p "
    << params_.p << ", zeta " << params_.zeta << " m^" << params_.p << " (force in the air " << params_.k * params_.zeta
    << " N)";
  return s.str();
}

nlohmann::json CoulombModel::configuration() const {
  return {{"type", "coulomb"}, {"mu", params_.mu}, {"K", params_.K}, {"k", params_.k}, {"p", params_.p}, {"zeta", params_.zeta}};
}

double CoulombModel::normalForce(double depth) const {
  return params_.k * (std::pow(std::max(depth, 0.0), params_.p) + params_.zeta);
}

void CoulombModel::evaluate(const std::vector<ContactFrame>& frames, const Terrain& terrain,
                            std::vector<ContactWrenches>& out, bool with_derivatives) const {
  const int K = params_.K;
  const double mu = params_.mu, p = params_.p, k = params_.k;
  if (out.size() != frames.size()) out.resize(frames.size());
  TerrainQuery q;
  Mat3 dt1_dn, dt2_dn;
  for (size_t b = 0; b < frames.size(); ++b) {
    const ContactFrame& f = frames[b];
    ContactWrenches& o = out[b];
    if (o.V.cols() != K) o.resize(K);
    terrain.query(f.position, q, with_derivatives);
    const Vec3& n = q.normal;
    Vec3 t1, t2;
    tangentBasis(n, t1, t2, with_derivatives ? &dt1_dn : nullptr, with_derivatives ? &dt2_dn : nullptr);
    const double r = f.radius;
    const double d = std::max(0.0, r - q.distance);
    // d^{p−1}; the usual integer exponents without pow().
    const double dp1 = !(d > 0.0) ? 0.0 : p == 3.0 ? d * d : p == 2.0 ? d : std::pow(d, p - 1.0);
    const double s = k * (dp1 * d + params_.zeta);             // k (d^p + ζ)
    // Column i of σ [−r n × u_i; u_i] with u_i = n + μ (cos φ_i t₁ + sin φ_i t₂): V for σ = s, and
    // on flat terrain dV for σ = ∂s. As n × t₁ = t₂ and n × t₂ = −t₁ it is cos φ_i A + sin φ_i B + C
    // with A = σ [−r μ t₂; μ t₁], B = σ [r μ t₁; μ t₂], C = σ [0; n]: whole 6-vectors, no cross
    // product per vertex.
    const auto fillCone = [&](double sigma, Mat6X& M) {
      const Vec3 T1 = (sigma * mu) * t1, T2 = (sigma * mu) * t2;
      Vec6 A, B, C;
      A.head<3>() = -r * T2;
      A.tail<3>() = T1;
      B.head<3>() = r * T1;
      B.tail<3>() = T2;
      C.head<3>().setZero();
      C.tail<3>() = sigma * n;
      for (int i = 0; i < K; ++i) M.col(i) = cos_[i] * A + sin_[i] * B + C;
    };
    fillCone(s, o.V);
    if (!with_derivatives) continue;

    // Rotations about the sphere centre change nothing: the model depends on the point only.
    for (int j = 0; j < 3; ++j) o.dV[j].setZero();
    // Translations: ∂d/∂p = −∇φ while in contact (d^p is C¹ at d = 0 for p ≥ 2), ∂n/∂p, ∂t/∂n ∂n/∂p.
    const double ds_dd = k * p * dp1;
    for (int j = 0; j < 3; ++j) {
      const double ds = d > 0.0 ? -ds_dd * q.gradient[j] : 0.0;
      const Vec3 dn = q.normal_jacobian.col(j);
      Mat6X& dV = o.dV[3 + j];
      if (dn.isZero(0.0)) {  // the normal does not turn (flat terrain): dt = darm = du = 0, the same values
        if (ds == 0.0)       // in the air, or a direction along the plane: cheaper than filling zeros
          dV.setZero();
        else
          fillCone(ds, dV);
        continue;
      }
      const Vec3 dt1 = dt1_dn * dn, dt2 = dt2_dn * dn;
      const Vec3 arm = -r * n, darm = -r * dn;  // the lowest point, from the centre
      for (int i = 0; i < K; ++i) {
        const Vec3 u = n + mu * (cos_[i] * t1 + sin_[i] * t2);
        const Vec3 du = dn + mu * (cos_[i] * dt1 + sin_[i] * dt2);
        const Vec3 F = s * u;
        const Vec3 dF = ds * u + s * du;
        dV.col(i).head<3>() = darm.cross(F) + arm.cross(dF);
        dV.col(i).tail<3>() = dF;
      }
    }
  }
}

const std::vector<std::string> kCoulombParameters = {"mu", "K", "k", "p", "zeta"};

namespace {
// readNumber's ranges are closed; a strictly positive parameter gets its own message.
double readPositive(const nlohmann::json& params, const std::string& key, double fallback, const ConfigContext& ctx,
                    double hi) {
  const double x = readNumber(params, key, fallback, ctx, -1e12, hi);
  if (!(x > 0.0)) throw InputError(ctx.where + "." + key + ": value " + jsonForMessage(params.at(key)) + " must be > 0");
  return x;
}
}  // namespace

std::unique_ptr<ContactModel> makeCoulombModel(const nlohmann::json& params, const ConfigContext& ctx) {
  std::vector<std::string> keys = kCoulombParameters;
  keys.push_back("type");
  requireKnownKeys(params, keys, ctx);
  CoulombParameters c;
  // Ranges far beyond use (μ of rubber on concrete ~1, the default k 1e6) that keep the cone finite.
  c.mu = readPositive(params, "mu", c.mu, ctx, 100.0);
  c.K = readInteger(params, "K", c.K, ctx, 3, limits::kMaxVertices);
  c.k = readPositive(params, "k", c.k, ctx, 1e15);
  c.p = readNumber(params, "p", c.p, ctx, 2.0, 10.0);
  c.zeta = readPositive(params, "zeta", c.zeta, ctx, 1.0);
  return std::make_unique<CoulombModel>(c);
}

}  // namespace nmdp
