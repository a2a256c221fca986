// Foot detection (detectFeet), the STL reader, and the "feet" and "default_gains" keys of `nmdp inspect`.
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "common/input_error.hpp"
#include "control/default_gains.hpp"
#include "control/gait.hpp"
#include "multibody/feet.hpp"
#include "multibody/kinematics.hpp"
#include "multibody/stl_mesh.hpp"
#include "test_support.hpp"
#include "test_temp_dir.hpp"

namespace nmdp::test {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::vector<std::string> footLinks(const std::vector<FootContact>& feet) {
  std::vector<std::string> names;
  for (const FootContact& f : feet) names.push_back(f.point.name);
  return names;
}

UrdfOptions robosimianPaperOptions() {
  UrdfOptions o;
  o.base = BaseType::Planar;
  for (int limb = 1; limb <= 4; ++limb)
    for (int j : {0, 1, 3, 5, 7}) o.locked_joints["limb" + std::to_string(limb) + "_joint" + std::to_string(j)] = 0.0;
  return o;
}

void writeText(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// UV sphere of the given radius about the origin: its vertices lie exactly on the sphere, with a
// ring on the equator and vertices at both poles.
std::vector<std::array<Vec3, 3>> uvSphere(double radius, int slices = 24, int stacks = 12) {
  auto point = [&](int i, int j) {
    const double theta = kPi * i / stacks, phi = 2 * kPi * j / slices;
    return Vec3(radius * std::sin(theta) * std::cos(phi), radius * std::sin(theta) * std::sin(phi), radius * std::cos(theta));
  };
  std::vector<std::array<Vec3, 3>> tris;
  for (int i = 0; i < stacks; ++i)
    for (int j = 0; j < slices; ++j) {
      const Vec3 a = point(i, j), b = point(i + 1, j), c = point(i + 1, j + 1), d = point(i, j + 1);
      if (i > 0) tris.push_back({a, b, d});
      if (i + 1 < stacks) tris.push_back({b, c, d});
    }
  return tris;
}

// Binary STL whose 80-byte header starts with "solid" (as many exporters write it).
void writeBinaryStl(const std::string& path, const std::vector<std::array<Vec3, 3>>& tris) {
  std::ofstream out(path, std::ios::binary);
  std::string header = "solid binary file with a misleading header";
  header.resize(80, ' ');
  out.write(header.data(), 80);
  const uint32_t n = static_cast<uint32_t>(tris.size());
  out.write(reinterpret_cast<const char*>(&n), 4);
  for (const auto& t : tris) {
    float values[12] = {0, 0, 0};
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) values[3 + 3 * k + c] = static_cast<float>(t[k][c]);
    out.write(reinterpret_cast<const char*>(values), sizeof values);
    const uint16_t attr = 0;
    out.write(reinterpret_cast<const char*>(&attr), 2);
  }
}

void writeAsciiStl(const std::string& path, const std::vector<std::array<Vec3, 3>>& tris) {
  std::ofstream out(path);
  out.precision(17);
  out << "solid ascii_sphere\n";
  for (const auto& t : tris) {
    out << "  facet normal 0 0 0\n    outer loop\n";
    for (const Vec3& v : t) out << "      vertex " << v.x() << " " << v.y() << " " << v.z() << "\n";
    out << "    endloop\n  endfacet\n";
  }
  out << "endsolid ascii_sphere\n";
}

// A small legged robot: a trunk (box) with one leg per entry of `feet` (hip and knee revolute,
// then a fixed foot link whose <collision> geometry is the entry), plus `extra` XML.
std::string legUrdf(const std::vector<std::string>& feet, const std::string& extra = "") {
  auto inertial = [](double m) {
    std::ostringstream s;
    s << "<inertial><mass value=\"" << m << "\"/><inertia ixx=\"0.001\" ixy=\"0\" ixz=\"0\" iyy=\"0.001\" iyz=\"0\" izz=\"0.001\"/></inertial>";
    return s.str();
  };
  std::ostringstream u;
  u << "<robot name=\"synthetic\">\n<link name=\"trunk\">" << inertial(5)
    << "<collision><geometry><box size=\"0.4 0.2 0.1\"/></geometry></collision></link>\n";
  for (size_t i = 0; i < feet.size(); ++i) {
    const std::string n = "leg" + std::to_string(i);
    const double x = 0.15 - 0.3 * static_cast<double>(i) / std::max<size_t>(1, feet.size() - 1);
    u << "<joint name=\"" << n << "_hip\" type=\"revolute\"><parent link=\"trunk\"/><child link=\"" << n
      << "_thigh\"/><origin xyz=\"" << x << " 0.1 0\"/><axis xyz=\"0 1 0\"/><limit effort=\"1\" velocity=\"1\" lower=\"-1\" upper=\"1\"/></joint>\n"
      << "<link name=\"" << n << "_thigh\">" << inertial(0.5)
      << "<collision><origin xyz=\"0 0 -0.1\"/><geometry><box size=\"0.03 0.03 0.2\"/></geometry></collision></link>\n"
      << "<joint name=\"" << n << "_knee\" type=\"revolute\"><parent link=\"" << n << "_thigh\"/><child link=\"" << n
      << "_shank\"/><origin xyz=\"0 0 -0.2\"/><axis xyz=\"0 1 0\"/><limit effort=\"1\" velocity=\"1\" lower=\"-1\" upper=\"1\"/></joint>\n"
      << "<link name=\"" << n << "_shank\">" << inertial(0.3)
      << "<collision><origin xyz=\"0 0 -0.08\"/><geometry><cylinder radius=\"0.01\" length=\"0.16\"/></geometry></collision></link>\n"
      << "<joint name=\"" << n << "_ankle\" type=\"fixed\"><parent link=\"" << n << "_shank\"/><child link=\"" << n
      << "_foot\"/><origin xyz=\"0 0 -0.2\"/></joint>\n"
      << "<link name=\"" << n << "_foot\">" << inertial(0.05) << feet[i] << "</link>\n";
  }
  u << extra << "</robot>\n";
  return u.str();
}

// ---------------------------------------------------------------------------------------------
// Our quadruped

TEST(Feet, QuadrupedHasFourSphereFeetUnderEveryBase) {
  for (BaseType base : {BaseType::Floating, BaseType::Planar, BaseType::Fixed}) {
    UrdfOptions options;
    options.base = base;
    const Model model = loadUrdf(quadrupedUrdf(), options);
    const auto feet = detectFeet(model);
    ASSERT_EQ(footLinks(feet), (std::vector<std::string>{"FL_foot", "FR_foot", "RL_foot", "RR_foot"}))
        << baseTypeName(base);
    for (const FootContact& f : feet) {
      EXPECT_EQ(f.point.offset, Vec3::Zero()) << f.point.name;
      EXPECT_DOUBLE_EQ(f.point.radius, 0.02) << f.point.name;
      EXPECT_EQ(f.source, "sphere");
      EXPECT_TRUE(f.warning.empty()) << f.warning;
      EXPECT_EQ(f.point.name.find("imu"), std::string::npos);
      EXPECT_EQ(f.point.name.find("rotor"), std::string::npos);
    }
  }
}

// A detected foot is a complete contact point: its link index names its link, and its leg axis is
// legAxisOf's (up the leg: +z in the quadruped's foot frames), as footContactPoints hands it on.
TEST(Feet, DetectedFootIsACompleteContactPoint) {
  const Model model = loadUrdf(quadrupedUrdf());
  const auto feet = detectFeet(model);
  const std::vector<ContactPoint> points = footContactPoints(model);
  ASSERT_EQ(points.size(), feet.size());
  for (size_t i = 0; i < feet.size(); ++i) {
    const ContactPoint& p = feet[i].point;
    EXPECT_EQ(p.link, model.linkIndex(p.name)) << p.name;
    EXPECT_EQ(p.leg_axis, legAxisOf(model, p.link, p.offset, p.radius)) << p.name;
    EXPECT_LT((p.leg_axis - Vec3::UnitZ()).norm(), 1e-12) << p.name;
    EXPECT_EQ(points[i].name, p.name);
    EXPECT_EQ(points[i].link, p.link);
    EXPECT_EQ(points[i].leg_axis, p.leg_axis);
  }
}

// ---------------------------------------------------------------------------------------------
// Real robots of ../shared

TEST(Feet, A1HasItsFourFootSpheres) {
  NMDP_REQUIRE_SHARED("robots/a1/urdf/a1.urdf");
  const Model model = loadUrdf(sharedPath("robots/a1/urdf/a1.urdf"));
  const auto feet = detectFeet(model);
  // URDF order; never imu_link nor the massless *_thigh_shoulder leaf cylinders.
  ASSERT_EQ(footLinks(feet), (std::vector<std::string>{"FR_foot", "FL_foot", "RR_foot", "RL_foot"}));
  for (const FootContact& f : feet) {
    EXPECT_EQ(f.point.offset, Vec3::Zero()) << f.point.name;
    EXPECT_DOUBLE_EQ(f.point.radius, 0.02) << f.point.name;
    EXPECT_EQ(f.source, "sphere");
  }
}

// Solo-12's feet are STL meshes: a wheel-like disc of radius 16 mm in the sagittal plane (x-z of
// the foot frame, centred on the frame origin), 4 mm wide with rounded edges and a hub. The cap
// estimator measures R = 0.01615 m at offset ≈ (2.7e-5, 0, 1.6e-4): the wheel's rolling radius
// about its centre (the lowest tessellated vertex is at z = -0.015993).
TEST(Feet, Solo12FeetAreFittedToTheLowestPointOfTheFootMesh) {
  NMDP_REQUIRE_SHARED("robots/solo12/urdf/solo12.urdf");
  const Model model = loadUrdf(sharedPath("robots/solo12/urdf/solo12.urdf"));
  const auto feet = detectFeet(model);
  ASSERT_EQ(footLinks(feet), (std::vector<std::string>{"FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"}));
  Data data(model);
  forwardKinematics(model, data, Eigen::VectorXd::Zero(model.nq));
  for (const FootContact& f : feet) {
    SCOPED_TRACE(f.point.name);
    EXPECT_EQ(f.source, "mesh cap");
    EXPECT_TRUE(f.warning.empty()) << f.warning;
    EXPECT_GT(f.point.radius, 0.0155);
    EXPECT_LT(f.point.radius, 0.0170);
    EXPECT_LT(f.point.offset.norm(), 1e-3);  // the wheel's centre is the foot frame origin

    // The lowest point of the leg: every readable collision-mesh vertex of the leg's links at q = 0.
    const int foot_link = model.linkIndex(f.point.name);
    double lowest = std::numeric_limits<double>::infinity();
    Vec3 lowest_point = Vec3::Zero();
    for (int l = foot_link; l >= 0 && model.links[l].body != model.root_body; l = model.links[l].parent_link) {
      for (const CollisionGeometry& g : model.links[l].collisions) {
        if (g.shape != CollisionGeometry::Shape::Mesh || g.mesh_file.empty()) continue;
        for (const Vec3& v : readStl(g.mesh_file).vertices) {
          const Vec3 w = linkPoint(model, data, l, g.translation + g.rotation * v.cwiseProduct(g.mesh_scale));
          if (w.z() < lowest) {
            lowest = w.z();
            lowest_point = w;
          }
        }
      }
    }
    const Vec3 centre = linkPoint(model, data, foot_link, f.point.offset);
    EXPECT_NEAR(centre.z() - f.point.radius, lowest, 1e-6);  // the sphere touches the lowest vertex
    EXPECT_LT((centre - lowest_point).head<2>().norm(), 3e-3);  // right above it
  }
}

// RoboSimian's limbs stretch out sideways at q = 0: the feet are the distal ends of limbN_link7,
// whose collision cylinder (r 0.05, length 0.15) runs along the link's x axis from its origin.
// The contact sphere is the one inscribed in the cylinder's far end: centre 0.10, tip at the
// end-cap centre x = 0.15.
void expectRoboSimianFeet(const Model& model) {
  const auto feet = detectFeet(model);
  ASSERT_EQ(footLinks(feet), (std::vector<std::string>{"limb1_link7", "limb2_link7", "limb3_link7", "limb4_link7"}));
  Data data(model);
  forwardKinematics(model, data, Eigen::VectorXd::Zero(model.nq));
  const Vec3 torso = linkPoint(model, data, model.linkIndex("torso"), Vec3::Zero());
  for (const FootContact& f : feet) {
    SCOPED_TRACE(f.point.name);
    EXPECT_EQ(f.source, "cylinder end");
    EXPECT_DOUBLE_EQ(f.point.radius, 0.05);
    EXPECT_LT((f.point.offset - Vec3(0.10, 0, 0)).norm(), 1e-4) << f.point.offset.transpose();
    const int link7 = model.linkIndex(f.point.name);
    const double tip = (linkPoint(model, data, link7, Vec3(0.15, 0, 0)) - torso).norm();
    const std::string limb = f.point.name.substr(0, 6);
    for (int l = 0; l < static_cast<int>(model.links.size()); ++l) {
      if (model.links[l].name.rfind(limb, 0) != 0) continue;
      EXPECT_LT((linkPoint(model, data, l, Vec3::Zero()) - torso).norm(), tip) << model.links[l].name;
    }
  }
}

TEST(Feet, RoboSimianAllActiveFeetAreTheDistalEndsOfLink7) {
  NMDP_REQUIRE_SHARED("robots/robosimian/robosimian_caesar_new_all_active.urdf");
  expectRoboSimianFeet(loadUrdf(sharedPath("robots/robosimian/robosimian_caesar_new_all_active.urdf")));
}

TEST(Feet, RoboSimianPaperPlanarLockedConfigurationKeepsTheSameFeet) {
  NMDP_REQUIRE_SHARED("robots/robosimian/robosimian_caesar_new_all_active.urdf");
  const Model model = loadUrdf(sharedPath("robots/robosimian/robosimian_caesar_new_all_active.urdf"), robosimianPaperOptions());
  ASSERT_EQ(model.nq, 15);
  expectRoboSimianFeet(model);
}

// ---------------------------------------------------------------------------------------------
// Synthetic robots: mesh feet (binary and ASCII), unreadable meshes, boxes, arms

TEST(Feet, MeshSphereFootIsRecoveredFromBinaryAndAsciiStl) {
  TempDir dir;
  writeBinaryStl(dir.file("unit_sphere.stl"), uvSphere(1.0));
  writeAsciiStl(dir.file("ball.stl"), uvSphere(0.03));
  const std::string binary_foot =
      "<collision><origin xyz=\"0 0 -0.01\"/><geometry><mesh filename=\"unit_sphere.stl\" scale=\"0.03 0.03 0.03\"/></geometry></collision>";
  const std::string ascii_foot =
      "<collision><origin xyz=\"0.005 0 -0.01\"/><geometry><mesh filename=\"ball.stl\"/></geometry></collision>";
  writeText(dir.file("robot.urdf"), legUrdf({binary_foot, ascii_foot}));
  const Model model = loadUrdf(dir.file("robot.urdf"));
  const auto feet = detectFeet(model);
  ASSERT_EQ(footLinks(feet), (std::vector<std::string>{"leg0_foot", "leg1_foot"}));
  EXPECT_NEAR(feet[0].point.radius, 0.03, 1e-6);
  EXPECT_LT((feet[0].point.offset - Vec3(0, 0, -0.01)).norm(), 1e-6) << feet[0].point.offset.transpose();
  EXPECT_NEAR(feet[1].point.radius, 0.03, 1e-6);
  EXPECT_LT((feet[1].point.offset - Vec3(0.005, 0, -0.01)).norm(), 1e-6) << feet[1].point.offset.transpose();
  for (const FootContact& f : feet) {
    EXPECT_EQ(f.source, "mesh cap");
    EXPECT_TRUE(f.warning.empty());
  }
}

TEST(Feet, UnreadableFootMeshFallsBackToTheLinkOriginWithAWarning) {
  TempDir dir;
  writeText(dir.file("broken.stl"), "this is not an STL file");
  const std::string missing = "<collision><geometry><mesh filename=\"missing.stl\"/></geometry></collision>";
  const std::string broken = "<collision><geometry><mesh filename=\"broken.stl\"/></geometry></collision>";
  writeText(dir.file("robot.urdf"), legUrdf({missing, broken}));
  const auto feet = detectFeet(loadUrdf(dir.file("robot.urdf")));
  ASSERT_EQ(footLinks(feet), (std::vector<std::string>{"leg0_foot", "leg1_foot"}));
  for (const FootContact& f : feet) {
    EXPECT_EQ(f.point.offset, Vec3::Zero());
    EXPECT_EQ(f.point.radius, 0.0);
    EXPECT_EQ(f.source, "link origin");
    EXPECT_NE(f.warning.find("could not be read"), std::string::npos) << f.warning;
  }
  EXPECT_NE(feet[1].warning.find("broken.stl"), std::string::npos) << feet[1].warning;
}

TEST(Feet, BoxAndCylinderFeetUseTheSphereInscribedAtTheirLowestEnd) {
  TempDir dir;
  const std::string box = "<collision><origin xyz=\"0 0 0.05\"/><geometry><box size=\"0.04 0.06 0.1\"/></geometry></collision>";
  const std::string upright = "<collision><origin xyz=\"0 0 0.02\"/><geometry><cylinder radius=\"0.015\" length=\"0.08\"/></geometry></collision>";
  const std::string wheel =
      "<collision><origin rpy=\"1.5707963267948966 0 0\"/><geometry><cylinder radius=\"0.03\" length=\"0.02\"/></geometry></collision>";
  writeText(dir.file("robot.urdf"), legUrdf({box, upright, wheel}));
  const auto feet = detectFeet(loadUrdf(dir.file("robot.urdf")));
  ASSERT_EQ(feet.size(), 3u);
  EXPECT_EQ(feet[0].source, "box face");
  EXPECT_DOUBLE_EQ(feet[0].point.radius, 0.02);  // smallest half-extent
  EXPECT_LT((feet[0].point.offset - Vec3(0, 0, 0.02)).norm(), 1e-12);  // touches the bottom face at z = 0
  EXPECT_EQ(feet[1].source, "cylinder end");
  EXPECT_DOUBLE_EQ(feet[1].point.radius, 0.015);
  EXPECT_LT((feet[1].point.offset - Vec3(0, 0, -0.005)).norm(), 1e-12);  // tip at the end cap z = -0.02
  EXPECT_EQ(feet[2].source, "cylinder side");
  EXPECT_DOUBLE_EQ(feet[2].point.radius, 0.03);
  EXPECT_LT(feet[2].point.offset.norm(), 1e-12);
}

TEST(Feet, SubtreesAboveTheTrunkAndSensorLeavesAreNotLegs) {
  TempDir dir;
  const std::string ball = "<collision><geometry><sphere radius=\"0.02\"/></geometry></collision>";
  // An arm on top of the trunk (its tip is above the trunk), a camera frame on the trunk, and a
  // geometry-less sensor frame on leg 0's shank, a sibling of the foot reaching farther down.
  const std::string extra =
      "<joint name=\"arm_joint\" type=\"revolute\"><parent link=\"trunk\"/><child link=\"arm\"/>"
      "<origin xyz=\"0 0 0.05\"/><axis xyz=\"0 0 1\"/><limit effort=\"1\" velocity=\"1\" lower=\"-1\" upper=\"1\"/></joint>"
      "<link name=\"arm\"><inertial><mass value=\"0.5\"/><inertia ixx=\"0.001\" ixy=\"0\" ixz=\"0\" iyy=\"0.001\" iyz=\"0\" izz=\"0.001\"/></inertial>"
      "<collision><origin xyz=\"0 0 0.15\"/><geometry><cylinder radius=\"0.02\" length=\"0.3\"/></geometry></collision></link>"
      "<joint name=\"camera_joint\" type=\"fixed\"><parent link=\"trunk\"/><child link=\"camera\"/><origin xyz=\"0.2 0 -0.3\"/></joint>"
      "<link name=\"camera\"><collision><geometry><box size=\"0.01 0.01 0.01\"/></geometry></collision></link>"
      "<joint name=\"leg0_sensor_joint\" type=\"fixed\"><parent link=\"leg0_shank\"/><child link=\"leg0_sensor\"/><origin xyz=\"0 0 -0.25\"/></joint>"
      "<link name=\"leg0_sensor\"/>";
  writeText(dir.file("robot.urdf"), legUrdf({ball, ball}, extra));
  const auto feet = detectFeet(loadUrdf(dir.file("robot.urdf")));
  EXPECT_EQ(footLinks(feet), (std::vector<std::string>{"leg0_foot", "leg1_foot"}));
}

// ---------------------------------------------------------------------------------------------
// STL reader

TEST(StlMesh, ReadsBinaryWithSolidHeaderAndAsciiAndRejectsBrokenFiles) {
  TempDir dir;
  const auto tris = uvSphere(0.5, 8, 4);
  writeBinaryStl(dir.file("b.stl"), tris);
  writeAsciiStl(dir.file("a.stl"), tris);
  const StlMesh b = readStl(dir.file("b.stl"));
  const StlMesh a = readStl(dir.file("a.stl"));
  EXPECT_TRUE(b.binary);
  EXPECT_FALSE(a.binary);
  EXPECT_EQ(a.name, "ascii_sphere");
  ASSERT_EQ(b.triangleCount(), static_cast<int>(tris.size()));
  ASSERT_EQ(a.triangleCount(), static_cast<int>(tris.size()));
  for (size_t t = 0; t < tris.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      EXPECT_LT((b.vertices[3 * t + k] - tris[t][k]).norm(), 1e-6);
      EXPECT_LT((a.vertices[3 * t + k] - tris[t][k]).norm(), 1e-12);
    }

  // Truncated binary, truncated ASCII, missing file: InputError naming the file.
  std::ifstream in(dir.file("b.stl"), std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  writeText(dir.file("short.stl"), bytes.substr(0, bytes.size() - 10));
  std::ifstream ain(dir.file("a.stl"));
  std::string text((std::istreambuf_iterator<char>(ain)), std::istreambuf_iterator<char>());
  writeText(dir.file("cut.stl"), text.substr(0, text.size() / 2));
  for (const std::string name : {"short.stl", "cut.stl", "absent.stl"}) {
    try {
      readStl(dir.file(name));
      ADD_FAILURE() << name << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
}

TEST(StlMesh, ReadsSolo12FootMeshAsBinaryDespiteItsSolidHeader) {
  NMDP_REQUIRE_SHARED("robots/solo12/urdf/meshes/stl/with_foot/solo_foot.stl");
  const StlMesh m = readStl(sharedPath("robots/solo12/urdf/meshes/stl/with_foot/solo_foot.stl"));
  EXPECT_TRUE(m.binary);
  EXPECT_EQ(m.triangleCount(), 3384);
  double zmin = 1, zmax = -1;
  for (const Vec3& v : m.vertices) {
    zmin = std::min(zmin, v.z());
    zmax = std::max(zmax, v.z());
  }
  EXPECT_NEAR(zmin, -0.016, 1e-4);
  EXPECT_NEAR(zmax, 0.016, 1e-4);
}

// ---------------------------------------------------------------------------------------------
// nmdp inspect

nlohmann::json runInspect(const std::string& args) {
  const std::string command = std::string(NMDP_BINARY) + " inspect " + args + " 2>/dev/null";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) throw std::runtime_error("cannot run " + command);
  std::string output;
  char buffer[4096];
  size_t n;
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) output.append(buffer, n);
  const int status = pclose(pipe);
  if (status != 0) throw std::runtime_error(command + " exited with status " + std::to_string(status));
  return nlohmann::json::parse(output);
}

void expectFeetKey(const nlohmann::json& out, const std::vector<std::string>& links, double radius, double tol) {
  ASSERT_TRUE(out.contains("feet"));
  const auto& feet = out["feet"];
  ASSERT_TRUE(feet.is_array());
  ASSERT_EQ(feet.size(), links.size());
  for (size_t i = 0; i < links.size(); ++i) {
    const auto& f = feet[i];
    ASSERT_TRUE(f.is_object());
    EXPECT_EQ(f.size(), 4u) << f.dump();  // exactly {link, offset, radius, leg_axis}
    EXPECT_EQ(f.at("link").get<std::string>(), links[i]);
    ASSERT_TRUE(f.at("offset").is_array());
    ASSERT_EQ(f.at("offset").size(), 3u);
    for (const auto& x : f.at("offset")) EXPECT_TRUE(x.is_number());
    EXPECT_NEAR(f.at("radius").get<double>(), radius, tol);
    ASSERT_EQ(f.at("leg_axis").size(), 3u);
    EXPECT_NEAR(std::hypot(f.at("leg_axis")[0].get<double>(), f.at("leg_axis")[1].get<double>(),
                           f.at("leg_axis")[2].get<double>()),
                1.0, 1e-12);
  }
}

TEST(InspectFeet, QuadrupedJsonHasTheFeetKey) {
  const nlohmann::json out = runInspect("'" + quadrupedUrdf() + "'");
  for (const char* key : {"dof", "joint_names", "total_mass", "links", "feet"}) EXPECT_TRUE(out.contains(key)) << key;
  expectFeetKey(out, {"FL_foot", "FR_foot", "RL_foot", "RR_foot"}, 0.02, 0.0);
  for (const auto& f : out["feet"]) {
    EXPECT_EQ(f["offset"], nlohmann::json::array({0.0, 0.0, 0.0}));
    EXPECT_NEAR(f["leg_axis"][2].get<double>(), 1.0, 1e-12);  // toward the knee, the foot link's +z
  }
  expectFeetKey(runInspect("'" + quadrupedUrdf() + "' --base fixed"), {"FL_foot", "FR_foot", "RL_foot", "RR_foot"}, 0.02, 0.0);
}

// `nmdp inspect` prints the default gains a scene gets: at the built-in gaits' standing pose, per
// actuated joint, with the rule, its frequency and damping ratio.
TEST(InspectFeet, QuadrupedJsonHasTheDefaultGains) {
  const nlohmann::json out = runInspect("'" + quadrupedUrdf() + "'");
  ASSERT_TRUE(out.contains("default_gains"));
  const nlohmann::json& g = out["default_gains"];
  EXPECT_EQ(g.at("frequency_hz").get<double>(), kDefaultGainFrequencyHz);
  EXPECT_EQ(g.at("damping_ratio").get<double>(), kDefaultGainDampingRatio);
  EXPECT_NE(g.at("rule").get<std::string>().find("H_jj"), std::string::npos);
  EXPECT_EQ(g.at("pose").get<std::string>(), "standing pose of the built-in gaits");
  EXPECT_EQ(g.at("feet").get<int>(), 4);
  const Model model = loadUrdf(quadrupedUrdf());
  const PdGains expected = defaultPdGains(model, standingPose(model, identifyQuadrupedLegs(model), {}).q);
  ASSERT_EQ(g.at("joints").size(), 12u);
  for (const auto& j : g.at("joints")) {
    const int i = model.dofIndex(j.at("joint").get<std::string>());
    ASSERT_GE(i, 0) << j.dump();
    EXPECT_EQ(j.at("kp").get<double>(), expected.kp[i]) << j.dump();  // printed with round-trip precision
    EXPECT_EQ(j.at("kd").get<double>(), expected.kd[i]) << j.dump();
    EXPECT_GT(j.at("load_inertia").get<double>(), 0.0) << j.dump();
    EXPECT_EQ(j.at("inertia").get<double>(), j.at("subtree_inertia").get<double>() + j.at("load_inertia").get<double>());
  }
  // A fixed base carries no load. (The output is kept: a range-for over a member of a temporary
  // would iterate freed memory.)
  const nlohmann::json fixed = runInspect("'" + quadrupedUrdf() + "' --base fixed");
  ASSERT_EQ(fixed.at("default_gains").at("joints").size(), 12u);
  for (const auto& j : fixed.at("default_gains").at("joints")) EXPECT_EQ(j.at("load_inertia").get<double>(), 0.0) << j.dump();
}

TEST(InspectFeet, RealRobotsJsonHasTheirFeet) {
  NMDP_REQUIRE_SHARED("robots");
  expectFeetKey(runInspect("'" + sharedPath("robots/a1/urdf/a1.urdf") + "'"), {"FR_foot", "FL_foot", "RR_foot", "RL_foot"}, 0.02, 0.0);
  expectFeetKey(runInspect("'" + sharedPath("robots/solo12/urdf/solo12.urdf") + "'"), {"FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"},
                0.016, 1e-3);
  std::string paper = "'" + sharedPath("robots/robosimian/robosimian_caesar_new_all_active.urdf") + "' --base planar";
  for (int limb = 1; limb <= 4; ++limb)
    for (int j : {0, 1, 3, 5, 7}) paper += " --lock limb" + std::to_string(limb) + "_joint" + std::to_string(j) + "=0";
  const nlohmann::json out = runInspect(paper);
  EXPECT_EQ(out["dof"], 15);
  expectFeetKey(out, {"limb1_link7", "limb2_link7", "limb3_link7", "limb4_link7"}, 0.05, 0.0);
  for (const auto& f : out["feet"]) {
    EXPECT_NEAR(f["offset"][0].get<double>(), 0.10, 1e-4);
    EXPECT_NEAR(f["leg_axis"][0].get<double>(), -1.0, 1e-8);  // back along the foot to its roll joint
  }
}

}  // namespace
}  // namespace nmdp::test
