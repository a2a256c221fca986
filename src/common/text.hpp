// Small text helpers for messages: lists, matrix shapes, the first bad entry of a matrix.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

namespace nmdp {

// "a, b, c" (or joined by `separator`).
std::string join(const std::vector<std::string>& items, const std::string& separator = ", ");

// "3 x 2": a matrix's rows and columns, as messages about array shapes print them.
std::string shapeText(Eigen::Index rows, Eigen::Index cols);
inline std::string shapeText(const Eigen::MatrixXd& m) { return shapeText(m.rows(), m.cols()); }

// "row r, column c" (0-based) of the first NaN or infinity of m in row-major order, "" if every
// entry is finite.
std::string firstNonFinite(const Eigen::MatrixXd& m);

}  // namespace nmdp
