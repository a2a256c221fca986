// The batched pieces both RBF feature functions share (rbf_function.hpp, the planar one, and
// spatial_rbf_function.hpp): the kernel over a column of squared distances, the product of a
// basis with coefficients stored packed, and the magnitude check of a model's numbers.
#pragma once
#include <Eigen/Dense>
#include <string>
#include <vector>

#include "contact_models/rbf_function.hpp"

namespace nmdp {

// Row-major coefficients and products (the layout of PlanarRows).
using RbfRows = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Columns of the product are computed in whole SIMD packets, rows in blocks of kRbfRowBlock.
constexpr int kRbfRowBlock = 4;
Eigen::Index rbfRoundUp(Eigen::Index n, Eigen::Index multiple);
// The column count of packed coefficients for C output columns (C rounded up to whole packets).
Eigen::Index rbfPackedColumns(Eigen::Index C);

// κ and g = κ'(ρ)/ρ elementwise for r2 = ρ² (the formulas of rbfKernel()): vectorized, writes
// `kappa` (r2.size() entries) and resizes nothing (g must have r2's size).
void rbfKernelColumn(RbfKernel kernel, double epsilon, const Eigen::ArrayXd& r2, double* kappa, Eigen::ArrayXd& g);

// out(0..R, :) = basis(:, 0..R)ᵀ coef, R a multiple of kRbfRowBlock; coef has rbfPackedColumns()
// columns, out at least R rows and as many columns. Each entry is one sum over the basis rows in
// order, so a row's result does not depend on the other rows.
void rbfProduct(const RbfRows& coef, const Eigen::MatrixXd& basis, Eigen::Index R, RbfRows& out);

// "" when every number lies within the limits of common/limits.hpp (kMaxRbfCentreCoordinate,
// kMaxRbfWeight, kMaxRbfScale), else what does not, e.g. "centre 3 has |beta| = 3e+306 > 1000".
// `feature_names` names the columns of `centres`.
std::string rbfMagnitudeProblem(const Eigen::MatrixXd& centres, const std::vector<std::string>& feature_names,
                                const Eigen::MatrixXd& weights, const Eigen::MatrixXd& polynomial,
                                const Eigen::VectorXd& scaling, double epsilon);

}  // namespace nmdp
