// Shared helpers for the test suite: where the robots are, the robot-parameterized fixture, random
// states, finite differences. See also test_temp_dir.hpp, test_cli.hpp, test_allocation_counter.hpp.
#pragma once
#include <gtest/gtest.h>

#include <filesystem>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <string>

#include "common/input_error.hpp"
#include "multibody/data.hpp"
#include "multibody/urdf_loader.hpp"
#include "random_values.hpp"

namespace nmdp::test {

inline std::string sourcePath(const std::string& rel) { return std::string(NMDP_SOURCE_DIR) + "/" + rel; }
inline std::string sharedPath(const std::string& rel) { return std::string(NMDP_SHARED_DIR) + "/" + rel; }
inline std::string quadrupedUrdf() { return sourcePath("models/quadruped/quadruped.urdf"); }

// Skips the current test with a message when ../shared (real robots, granular data) is absent.
#define NMDP_REQUIRE_SHARED(rel)                                                                    \
  do {                                                                                              \
    if (!std::filesystem::exists(::nmdp::test::sharedPath(rel)))                                   \
      GTEST_SKIP() << "../shared is absent (" << ::nmdp::test::sharedPath(rel) << "): skipping";     \
  } while (0)

struct RobotCase {
  std::string name;
  std::string path;  // absolute
  UrdfOptions options;
  bool shared = false;
};
inline void PrintTo(const RobotCase& c, std::ostream* os) { *os << c.name; }

// The robots every derivative test runs on: the project's quadruped (three bases) and the real
// robots of ../shared (A1, Solo-12, RoboSimian all-active with massless link0, and RoboSimian
// in the paper's planar configuration).
inline std::vector<RobotCase> derivativeRobots() {
  std::vector<RobotCase> out;
  UrdfOptions floating, planar, fixed;
  planar.base = BaseType::Planar;
  fixed.base = BaseType::Fixed;
  out.push_back({"quadruped_floating", quadrupedUrdf(), floating, false});
  out.push_back({"quadruped_planar", quadrupedUrdf(), planar, false});
  out.push_back({"quadruped_fixed", quadrupedUrdf(), fixed, false});
  out.push_back({"a1", sharedPath("robots/a1/urdf/a1.urdf"), floating, true});
  out.push_back({"solo12", sharedPath("robots/solo12/urdf/solo12.urdf"), floating, true});
  out.push_back({"robosimian", sharedPath("robots/robosimian/robosimian_caesar_new_all_active.urdf"), floating, true});
  UrdfOptions paper;  // planar base, joints 2, 4, 6 of each limb active, the rest locked at 0
  paper.base = BaseType::Planar;
  for (int limb = 1; limb <= 4; ++limb)
    for (int j : {0, 1, 3, 5, 7}) paper.locked_joints["limb" + std::to_string(limb) + "_joint" + std::to_string(j)] = 0.0;
  out.push_back({"robosimian_paper_planar", sharedPath("robots/robosimian/robosimian_caesar_new_all_active.urdf"), paper, true});
  return out;
}

// A test parameterized by the robots of derivativeRobots(): SetUp skips with a message when the
// robot is one of ../shared and that is absent, and loads the model otherwise. A fixture that
// extends SetUp calls RobotTest::SetUp() first and returns when IsSkipped().
class RobotTest : public ::testing::TestWithParam<RobotCase> {
 protected:
  void SetUp() override {
    if (GetParam().shared && !std::filesystem::exists(GetParam().path))
      GTEST_SKIP() << "../shared is absent (" << GetParam().path << "): skipping";
    model = loadUrdf(GetParam().path, GetParam().options);
  }
  Model model;
};

// The message of the nmdp::InputError that f() throws; a failure (and "") when it throws anything
// else or nothing.
inline std::string inputErrorMessage(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected nmdp::InputError, got another exception: " << e.what();
    return "";
  }
  ADD_FAILURE() << "expected nmdp::InputError, nothing was thrown";
  return "";
}

// Central finite difference of a vector function: column j = (f(x + e_j ε) − f(x − e_j ε)) / 2ε.
inline Eigen::MatrixXd centralDifference(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f,
                                         const Eigen::VectorXd& x, double eps) {
  const Eigen::VectorXd f0 = f(x);
  Eigen::MatrixXd J(f0.size(), x.size());
  for (int j = 0; j < x.size(); ++j) {
    Eigen::VectorXd xp = x, xm = x;
    xp[j] += eps;
    xm[j] -= eps;
    J.col(j) = (f(xp) - f(xm)) / (2 * eps);
  }
  return J;
}

// max |A − B| relative to the largest entry of B (at least `floor`).
inline double relativeError(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, double floor = 1e-12) {
  return (A - B).cwiseAbs().maxCoeff() / std::max(B.cwiseAbs().maxCoeff(), floor);
}

// max |A − B| in units in the last place of the largest entry of A and B: how far apart two different
// computations of one quantity are (another BLAS kernel, another summation order), for a bound of a
// few ulps where bit-identity would hold on one CPU only. 0 for equal matrices, infinity for
// different shapes or a NaN.
inline double ulpsOfLargest(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
  if (A.rows() != B.rows() || A.cols() != B.cols()) return std::numeric_limits<double>::infinity();
  if (A.size() == 0) return 0.0;
  const double largest = std::max(A.cwiseAbs().maxCoeff(), B.cwiseAbs().maxCoeff());
  const double difference = (A - B).cwiseAbs().maxCoeff();
  if (std::isnan(largest) || std::isnan(difference)) return std::numeric_limits<double>::infinity();
  if (difference == 0.0) return 0.0;
  return difference / (std::nextafter(largest, std::numeric_limits<double>::infinity()) - largest);
}

}  // namespace nmdp::test
