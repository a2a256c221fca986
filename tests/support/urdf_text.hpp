// Fixture URDFs written by the tests: links, joints and inertials in full precision, and the total
// mass a URDF file declares, scanned from its text.
#pragma once
#include <gtest/gtest.h>

#include <fstream>
#include <iomanip>
#include <regex>
#include <sstream>
#include <string>

#include "multibody/spatial.hpp"

namespace nmdp::test {

// Full-precision text of a number, so generated URDFs carry exactly the values the test uses.
inline std::string num(double v) {
  std::ostringstream s;
  s << std::setprecision(17) << v;
  return s.str();
}
inline std::string vec(const Vec3& v) { return num(v.x()) + " " + num(v.y()) + " " + num(v.z()); }

// URDF rpy: R = Rz(yaw) Ry(pitch) Rx(roll).
inline Mat3 rpyMatrix(const Vec3& rpy) {
  return (Eigen::AngleAxisd(rpy.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Vec3::UnitY()) *
          Eigen::AngleAxisd(rpy.x(), Vec3::UnitX()))
      .toRotationMatrix();
}

struct InertialSpec {
  double mass = 0;
  Vec3 xyz = Vec3::Zero();
  Vec3 rpy = Vec3::Zero();
  Mat3 I = Mat3::Zero();  // about the com, in the inertial frame
};

inline std::string inertialXml(const InertialSpec& s) {
  return "    <inertial>\n      <origin xyz=\"" + vec(s.xyz) + "\" rpy=\"" + vec(s.rpy) + "\"/>\n      <mass value=\"" +
         num(s.mass) + "\"/>\n      <inertia ixx=\"" + num(s.I(0, 0)) + "\" ixy=\"" + num(s.I(0, 1)) + "\" ixz=\"" +
         num(s.I(0, 2)) + "\" iyy=\"" + num(s.I(1, 1)) + "\" iyz=\"" + num(s.I(1, 2)) + "\" izz=\"" + num(s.I(2, 2)) +
         "\"/>\n    </inertial>\n";
}
inline std::string linkXml(const std::string& name, const InertialSpec* inertial) {
  if (!inertial) return "  <link name=\"" + name + "\"/>\n";
  return "  <link name=\"" + name + "\">\n" + inertialXml(*inertial) + "  </link>\n";
}
inline std::string jointXml(const std::string& name, const std::string& type, const std::string& parent,
                     const std::string& child, const Vec3& xyz, const Vec3& rpy, const Vec3& axis = Vec3::UnitZ()) {
  std::string s = "  <joint name=\"" + name + "\" type=\"" + type + "\">\n    <parent link=\"" + parent +
                  "\"/>\n    <child link=\"" + child + "\"/>\n    <origin xyz=\"" + vec(xyz) + "\" rpy=\"" + vec(rpy) +
                  "\"/>\n";
  if (type != "fixed") s += "    <axis xyz=\"" + vec(axis) + "\"/>\n";
  if (type == "revolute" || type == "prismatic")
    s += "    <limit lower=\"-3\" upper=\"3\" effort=\"10\" velocity=\"10\"/>\n";
  return s + "  </joint>\n";
}
inline std::string robotXml(const std::string& name, const std::string& body) {
  return "<?xml version=\"1.0\"?>\n<robot name=\"" + name + "\">\n" + body + "</robot>\n";
}

// A symmetric positive definite inertia with off-diagonal terms.
inline Mat3 inertiaMatrix(double a, double b, double c, double xy, double xz, double yz) {
  Mat3 I;
  I << a, xy, xz, xy, b, yz, xz, yz, c;
  return I;
}

// Sum of every <mass value="..."> outside XML comments, scanned from the file text.
inline double scanUrdfMass(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str(), stripped;
  for (size_t pos = 0;;) {
    const size_t open = text.find("<!--", pos);
    stripped += text.substr(pos, open == std::string::npos ? std::string::npos : open - pos);
    if (open == std::string::npos) break;
    const size_t close = text.find("-->", open + 4);
    if (close == std::string::npos) break;
    pos = close + 3;
  }
  const std::regex mass_re("<mass\\s+value\\s*=\\s*\"([^\"]+)\"");
  double sum = 0;
  int count = 0;
  for (std::sregex_iterator it(stripped.begin(), stripped.end(), mass_re), end; it != end; ++it) {
    sum += std::stod((*it)[1].str());
    ++count;
  }
  EXPECT_GT(count, 0) << path;
  return sum;
}

}  // namespace nmdp::test
