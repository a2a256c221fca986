// The URDF edits that let MuJoCo's own URDF importer load our robots from memory, shared by the
// MuJoCo oracle test (tests/multibody/test_mujoco_oracle.cpp) and the side-by-side benchmark
// (bench/bench_mujoco.cpp). See the oracle test's header comment for why each edit is made:
// <visual> elements removed, a <mujoco><compiler/></mujoco> element that turns off MuJoCo's
// inertia alterations, and non-diagonal inertias restated exactly in their principal axes.
#pragma once
#include <mujoco/mujoco.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "multibody/spatial.hpp"

namespace nmdp::test {

struct MjModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct MjDataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
struct VfsDeleter {
  void operator()(mjVFS* v) const {
    mj_deleteVFS(v);
    delete v;
  }
};
using MjModelPtr = std::unique_ptr<mjModel, MjModelDeleter>;
using MjDataPtr = std::unique_ptr<mjData, MjDataDeleter>;

inline std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// URDF rotation of rpy = (roll, pitch, yaw): Rz(yaw) Ry(pitch) Rx(roll).
inline Mat3 rpyMatrix(const Vec3& rpy) {
  return (Eigen::AngleAxisd(rpy.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Vec3::UnitY()) *
          Eigen::AngleAxisd(rpy.x(), Vec3::UnitX()))
      .toRotationMatrix();
}

inline Vec3 rpyOf(const Mat3& R) {
  return Vec3(std::atan2(R(2, 1), R(2, 2)), std::atan2(-R(2, 0), std::hypot(R(0, 0), R(1, 0))),
              std::atan2(R(1, 0), R(0, 0)));
}

// Attribute `name` of the first element `tag` in `xml` ("" when absent).
inline std::string attribute(const std::string& xml, const std::string& tag, const std::string& name) {
  std::smatch element, value;
  if (!std::regex_search(xml, element, std::regex("<" + tag + R"(\b[^>]*>)"))) return "";
  const std::string text = element.str(0);
  if (!std::regex_search(text, value, std::regex(R"(\b)" + name + R"(\s*=\s*["']([^"']*)["'])"))) return "";
  return value.str(1);
}

inline double number(const std::string& text, double fallback = 0.0) { return text.empty() ? fallback : std::stod(text); }

inline Vec3 triple(const std::string& text) {
  Vec3 v = Vec3::Zero();
  std::istringstream in(text);
  in >> v.x() >> v.y() >> v.z();
  return v;
}

inline std::string format17(double x) {
  char buffer[40];
  std::snprintf(buffer, sizeof(buffer), "%.17g", x);
  return buffer;
}

// Rewrites every <inertial> whose inertia is not diagonal in its frame into the same inertia in
// its principal axes: origin rpy = R_origin · V, inertia = diag(λ) with λ in decreasing order.
//
// Why: MuJoCo's compiler diagonalises each full inertia with a Jacobi iteration (mjuu_eig3) that
// stops once the next rotation's cosine exceeds 1 − 1e-12, i.e. once the remaining angle is below
// ≈ 1.4e-6 rad. That leaves errors of up to ~1e-7 relative in A1's link inertias (e.g. FR_thigh
// iyz −2.2447391e-05 instead of −2.2448e-05), which reach H at ~3e-8: MuJoCo's importer
// precision, not a dynamics disagreement (the RawUrdf test below measures it). Given an exactly
// diagonal inertia in decreasing order, eig3 returns it untouched. The physical inertia is
// unchanged, which is checked here to 1e-14.
inline std::string principalAxesInertials(const std::string& urdf) {
  const std::regex block(R"(<inertial\b[^>]*>[\s\S]*?</inertial>)");
  std::string out;
  std::size_t last = 0;
  for (auto it = std::sregex_iterator(urdf.begin(), urdf.end(), block); it != std::sregex_iterator(); ++it) {
    const std::string xml = it->str(0);
    out += urdf.substr(last, it->position(0) - last);
    last = it->position(0) + it->length(0);
    Mat3 I;
    I << number(attribute(xml, "inertia", "ixx")), number(attribute(xml, "inertia", "ixy")),
        number(attribute(xml, "inertia", "ixz")), number(attribute(xml, "inertia", "ixy")),
        number(attribute(xml, "inertia", "iyy")), number(attribute(xml, "inertia", "iyz")),
        number(attribute(xml, "inertia", "ixz")), number(attribute(xml, "inertia", "iyz")),
        number(attribute(xml, "inertia", "izz"));
    if (I(0, 1) == 0.0 && I(0, 2) == 0.0 && I(1, 2) == 0.0) {  // already principal: keep the text
      out += xml;
      continue;
    }
    const Mat3 R0 = rpyMatrix(triple(attribute(xml, "origin", "rpy")));
    const Vec3 xyz = triple(attribute(xml, "origin", "xyz"));
    Eigen::SelfAdjointEigenSolver<Mat3> eig(I);
    const Vec3 lambda = eig.eigenvalues().reverse();            // decreasing
    const Mat3 V0 = eig.eigenvectors().rowwise().reverse();    // matching columns
    // A proper rotation whose rpy reproduces it exactly (avoid gimbal lock with column signs).
    Mat3 R = Mat3::Zero();
    Vec3 rpy = Vec3::Zero();
    double best = 1.0;
    for (const Vec3& sign : {Vec3(1, 1, 1), Vec3(-1, -1, 1), Vec3(-1, 1, -1), Vec3(1, -1, -1)}) {
      Mat3 V = V0 * sign.asDiagonal();
      if (V.determinant() < 0) V.col(2) *= -1;
      const Mat3 candidate = R0 * V;
      const Vec3 angles = rpyOf(candidate);
      const double error = (rpyMatrix(angles) - candidate).cwiseAbs().maxCoeff();
      if (error < best) best = error, R = candidate, rpy = angles;
    }
    const Mat3 original = R0 * I * R0.transpose(), rebuilt = rpyMatrix(rpy) * lambda.asDiagonal() * rpyMatrix(rpy).transpose();
    if (best > 1e-14 || (rebuilt - original).cwiseAbs().maxCoeff() > 1e-14 * original.cwiseAbs().maxCoeff())
      throw std::runtime_error("principal-axes rewrite is inexact for inertial:\n" + xml);
    out += "<inertial>\n      <origin xyz=\"" + format17(xyz.x()) + " " + format17(xyz.y()) + " " + format17(xyz.z()) +
           "\" rpy=\"" + format17(rpy.x()) + " " + format17(rpy.y()) + " " + format17(rpy.z()) +
           "\"/>\n      <mass value=\"" + attribute(xml, "mass", "value") + "\"/>\n      <inertia ixx=\"" +
           format17(lambda.x()) + "\" ixy=\"0\" ixz=\"0\" iyy=\"" + format17(lambda.y()) + "\" iyz=\"0\" izz=\"" +
           format17(lambda.z()) + "\"/>\n    </inertial>";
  }
  return out + urdf.substr(last);
}

// The URDF text MuJoCo is given: visuals removed, compiler options injected after <robot ...>,
// and (unless `raw`) inertias rewritten in their principal axes.
inline std::string urdfForMujoco(const std::string& urdf, bool fusestatic, bool raw = false) {
  std::string text = std::regex_replace(urdf, std::regex(R"(<visual\b[\s\S]*?</visual>)"), "");
  text = std::regex_replace(text, std::regex(R"(<visual\b[^>]*/>)"), "");
  if (!raw) text = principalAxesInertials(text);
  const std::smatch robot = [&] {
    std::smatch m;
    if (!std::regex_search(text, m, std::regex(R"(<robot\b[^>]*>)")))
      throw std::runtime_error("no <robot> element");
    return m;
  }();
  const std::string compiler = std::string("\n  <mujoco><compiler inertiafromgeom=\"false\" balanceinertia=\"false\" "
                                           "boundmass=\"0\" boundinertia=\"0\" settotalmass=\"-1\" "
                                           "discardvisual=\"true\" fusestatic=\"") +
                               (fusestatic ? "true" : "false") + "\"/></mujoco>\n";
  const auto at = robot.position(0) + robot.length(0);
  return text.substr(0, at) + compiler + text.substr(at);
}

// Loads a URDF text through MuJoCo's importer from a virtual file system; errors are returned in
// `error` (the model is null then).
inline MjModelPtr loadMujocoFromMemory(const std::string& text, const std::string& name, std::string& error) {
  std::unique_ptr<mjVFS, VfsDeleter> vfs(new mjVFS);  // ~2 MB: not on the stack
  mj_defaultVFS(vfs.get());
  if (mj_makeEmptyFileVFS(vfs.get(), name.c_str(), static_cast<int>(text.size())) != 0) {
    error = "mj_makeEmptyFileVFS failed";
    return nullptr;
  }
  const int index = mj_findFileVFS(vfs.get(), name.c_str());
  std::memcpy(vfs->filedata[index], text.data(), text.size());
  char buffer[2048] = "";
  MjModelPtr m(mj_loadXML(name.c_str(), vfs.get(), buffer, sizeof(buffer)));
  if (!m) error = std::string("mj_loadXML(") + name + "): " + buffer;
  else if (buffer[0]) error = std::string("mj_loadXML warning: ") + buffer;  // informational only
  return m;
}

}  // namespace nmdp::test
