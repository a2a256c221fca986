#include "contact_models/rbf_basis.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/limits.hpp"

namespace nmdp {

namespace {

// The product basisᵀ · coefficients. Eigen's GEMM repacks the constant coefficients on every call
// (a third of its time at this size); here they are stored packed (row-major, padded to whole
// packets) and streamed by a 4-row × 3-packet register block: 12 accumulators, 3 loads and 4
// broadcasts per centre, within the 16 SIMD registers of AVX2 (or SSE).
using Packet = Eigen::internal::packet_traits<double>::type;
constexpr int kPacket = Eigen::internal::packet_traits<double>::size;
constexpr int kRowBlock = kRbfRowBlock;
constexpr int kColBlock = 3;

// out(0..3, 0..CB·P) = Σ_i basis(i, 0..3)ᵀ coef(i, 0..CB·P), i = 0..M−1 in order. basis is
// column-major with leading dimension M; coef and out are row-major.
template <int CB>
void productBlock(const double* coef, Eigen::Index coef_stride, const double* basis, Eigen::Index M, double* out,
                  Eigen::Index out_stride) {
  using namespace Eigen::internal;
  Packet acc[kRowBlock][CB];
  for (int r = 0; r < kRowBlock; ++r)
    for (int k = 0; k < CB; ++k) acc[r][k] = pset1<Packet>(0.0);
  for (Eigen::Index i = 0; i < M; ++i) {
    Packet c[CB];
    for (int k = 0; k < CB; ++k) c[k] = ploadu<Packet>(coef + i * coef_stride + k * kPacket);
    for (int r = 0; r < kRowBlock; ++r) {
      const Packet s = pset1<Packet>(basis[r * M + i]);
      for (int k = 0; k < CB; ++k) acc[r][k] = pmadd(s, c[k], acc[r][k]);
    }
  }
  for (int r = 0; r < kRowBlock; ++r)
    for (int k = 0; k < CB; ++k) pstoreu(out + r * out_stride + k * kPacket, acc[r][k]);
}

}  // namespace

Eigen::Index rbfRoundUp(Eigen::Index n, Eigen::Index m) { return (n + m - 1) / m * m; }

Eigen::Index rbfPackedColumns(Eigen::Index C) { return rbfRoundUp(C, kPacket); }

void rbfProduct(const RbfRows& coef, const Eigen::MatrixXd& basis, Eigen::Index R, RbfRows& out) {
  const Eigen::Index M = coef.rows(), C = coef.cols(), packets = C / kPacket;
  for (Eigen::Index c0 = 0; c0 < packets; c0 += kColBlock) {
    const double* cp = coef.data() + c0 * kPacket;
    for (Eigen::Index r0 = 0; r0 < R; r0 += kRowBlock) {
      const double* bp = basis.data() + r0 * M;
      double* op = out.data() + r0 * C + c0 * kPacket;
      switch (std::min<Eigen::Index>(kColBlock, packets - c0)) {
        case 3: productBlock<3>(cp, C, bp, M, op, C); break;
        case 2: productBlock<2>(cp, C, bp, M, op, C); break;
        default: productBlock<1>(cp, C, bp, M, op, C); break;
      }
    }
  }
}

void rbfKernelColumn(RbfKernel kernel, double epsilon, const Eigen::ArrayXd& r2, double* kappa_data, Eigen::ArrayXd& g) {
  const Eigen::Index N = r2.size();
  const double e2 = epsilon * epsilon;
  Eigen::Map<Eigen::ArrayXd> kappa(kappa_data, N);
  switch (kernel) {
    case RbfKernel::ThinPlate:
      // Eigen 3.4.0's select() is not vectorized: mask the centre afterwards instead.
      g = r2.log();  // −inf at a centre
      kappa = 0.5 * r2 * g;
      g += 1.0;
      if (!(r2.minCoeff() > 0.0))
        for (Eigen::Index i = 0; i < N; ++i)
          if (!(r2[i] > 0.0)) kappa[i] = g[i] = 0.0;
      break;
    case RbfKernel::Gaussian:
      kappa = (-e2 * r2).exp();
      g = (-2.0 * e2) * kappa;
      break;
    case RbfKernel::Multiquadric:
      kappa = (1.0 + e2 * r2).sqrt();
      g = e2 / kappa;
      break;
    case RbfKernel::InverseMultiquadric:
      kappa = (1.0 + e2 * r2).rsqrt();
      g = -e2 * kappa.cube();
      break;
    case RbfKernel::Cubic:
      g = r2.sqrt();
      kappa = r2 * g;
      g *= 3.0;
      break;
    case RbfKernel::Linear:
      kappa = r2.sqrt();
      g = kappa.inverse();
      if (!(r2.minCoeff() > 0.0))
        for (Eigen::Index i = 0; i < N; ++i)
          if (!(r2[i] > 0.0)) g[i] = 0.0;  // zero subgradient at a centre
      break;
  }
}

std::string rbfMagnitudeProblem(const Eigen::MatrixXd& centres, const std::vector<std::string>& feature_names,
                                const Eigen::MatrixXd& weights, const Eigen::MatrixXd& polynomial,
                                const Eigen::VectorXd& scaling, double epsilon) {
  const auto number = [](double x) {
    std::ostringstream out;
    out << x;
    return out.str();
  };
  for (Eigen::Index i = 0; i < centres.rows(); ++i)
    for (Eigen::Index c = 0; c < centres.cols(); ++c)
      if (!(std::abs(centres(i, c)) <= limits::kMaxRbfCentreCoordinate))
        return "centre " + std::to_string(i + 1) + " has |" +
               (c < static_cast<Eigen::Index>(feature_names.size()) ? feature_names[c] : "feature " + std::to_string(c + 1)) +
               "| = " + number(std::abs(centres(i, c))) + " > " + number(limits::kMaxRbfCentreCoordinate);
  const auto largest = [](const Eigen::MatrixXd& m) { return m.size() == 0 ? 0.0 : m.cwiseAbs().maxCoeff(); };
  if (!(largest(weights) <= limits::kMaxRbfWeight))
    return "a weight of magnitude " + number(largest(weights)) + " > " + number(limits::kMaxRbfWeight);
  if (!(largest(polynomial) <= limits::kMaxRbfWeight))
    return "a polynomial coefficient of magnitude " + number(largest(polynomial)) + " > " + number(limits::kMaxRbfWeight);
  if (!(scaling.maxCoeff() <= limits::kMaxRbfScale))
    return "a feature scaling of " + number(scaling.maxCoeff()) + " > " + number(limits::kMaxRbfScale);
  if (!(epsilon <= limits::kMaxRbfScale)) return "epsilon = " + number(epsilon) + " > " + number(limits::kMaxRbfScale);
  return "";
}

}  // namespace nmdp
