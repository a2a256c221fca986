// Bad input through the CLI (`nmdp inspect`) and the library: every malformed URDF or option gives
// exactly one line on stderr that names the file and the offending element, exit code 1 and no
// crash; the library throws nmdp::InputError with the same information and prints nothing.
#include <cstring>
#include <optional>
#include <regex>

#include "common/input_error.hpp"
#include "test_cli.hpp"
#include "test_support.hpp"

namespace nmdp::test {
namespace {

// ---- fixture URDFs --------------------------------------------------------------------------------

std::string inertial(const std::string& mass, const std::string& ixx = "0.01") {
  return "    <inertial>\n"
         "      <origin xyz=\"0 0 0\" rpy=\"0 0 0\"/>\n"
         "      <mass value=\"" + mass + "\"/>\n"
         "      <inertia ixx=\"" + ixx + "\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/>\n"
         "    </inertial>\n";
}
std::string link(const std::string& name, const std::string& mass = "1.0", const std::string& ixx = "0.01") {
  return "  <link name=\"" + name + "\">\n" + inertial(mass, ixx) + "  </link>\n";
}
std::string joint(const std::string& name, const std::string& type, const std::string& parent, const std::string& child,
                  bool limits = true) {
  std::string s = "  <joint name=\"" + name + "\" type=\"" + type + "\">\n    <parent link=\"" + parent +
                  "\"/>\n    <child link=\"" + child + "\"/>\n    <origin xyz=\"0 0 -0.2\" rpy=\"0 0 0\"/>\n";
  if (type != "fixed") s += "    <axis xyz=\"0 1 0\"/>\n";
  if (limits && (type == "revolute" || type == "prismatic"))
    s += "    <limit lower=\"-2\" upper=\"2\" effort=\"20\" velocity=\"10\"/>\n";
  return s + "  </joint>\n";
}
std::string robot(const std::string& body) { return "<?xml version=\"1.0\"?>\n<robot name=\"leg\">\n" + body + "</robot>\n"; }

// A valid three-link leg the bad cases are variations of.
std::string goodLeg() {
  return robot(link("hip_link", "2.0") + joint("thigh_joint", "revolute", "hip_link", "thigh_link") + link("thigh_link") +
               joint("knee_joint", "revolute", "thigh_link", "calf_link") + link("calf_link", "0.5"));
}

struct BadCase {
  std::string name;
  std::string file_name;                   // written into the temp dir unless `content` is null
  std::optional<std::string> content;     // nullopt: the file does not exist
  std::vector<std::string> options;        // extra CLI options after the file
  UrdfOptions library_options;             // the same options for loadUrdf
  std::vector<std::string> expect;         // substrings the message must contain
  std::string line_regex;                  // if set: the message must match "<file>:(line_regex):"
  bool names_file = true;
};

void PrintTo(const BadCase& c, std::ostream* os) { *os << c.name; }

std::vector<BadCase> badCases() {
  std::vector<BadCase> cases;
  auto add = [&](BadCase c) { cases.push_back(std::move(c)); };

  add({"missing_file", "no_such_robot.urdf", std::nullopt, {}, {}, {"no such file"}, "", true});

  // <inertial> opened on line 4 and never closed; the parser notices at </link> on line 7.
  add({"malformed_xml_unclosed_tag", "unclosed.urdf",
       std::string("<?xml version=\"1.0\"?>\n"
                   "<robot name=\"leg\">\n"
                   "  <link name=\"hip_link\">\n"
                   "    <inertial>\n"
                   "      <mass value=\"1\"/>\n"
                   "      <inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/>\n"
                   "  </link>\n"
                   "</robot>\n"),
       {}, {}, {"malformed XML"}, "4|7", true});

  add({"malformed_xml_truncated", "truncated.urdf", std::string("<?xml version=\"1.0\"?>\n<robot name=\"leg\">\n  <link name=\"a\"\n"),
       {}, {}, {"malformed XML"}, "[0-9]+", true});

  add({"empty_file", "empty.urdf", std::string(""), {}, {}, {"malformed XML"}, "", true});

  add({"not_urdf", "page.urdf", std::string("<?xml version=\"1.0\"?>\n<html>\n  <body>hello</body>\n</html>\n"), {}, {},
       {"<robot>"}, "", true});

  add({"unknown_joint_type", "ball.urdf",
       robot(link("hip_link", "2.0") + joint("shoulder_joint", "ball", "hip_link", "thigh_link") + link("thigh_link")), {}, {},
       {"<joint name=\"shoulder_joint\">", "\"ball\"", "revolute", "continuous", "prismatic", "fixed"}, "", true});

  add({"nan_inertia", "nan_inertia.urdf",
       robot(link("hip_link", "2.0") + joint("thigh_joint", "revolute", "hip_link", "thigh_link") +
             link("thigh_link", "1.0", "nan")),
       {}, {}, {"thigh_link", "ixx"}, "", true});

  add({"inf_inertia", "inf_inertia.urdf",
       robot(link("hip_link", "2.0") + joint("thigh_joint", "revolute", "hip_link", "thigh_link") +
             link("thigh_link", "1.0", "inf")),
       {}, {}, {"thigh_link", "ixx"}, "", true});

  add({"non_numeric_inertia", "abc_inertia.urdf",
       robot(link("hip_link", "2.0") + joint("thigh_joint", "revolute", "hip_link", "thigh_link") +
             link("thigh_link", "1.0", "abc")),
       {}, {}, {"thigh_link", "ixx"}, "", true});

  add({"nan_mass", "nan_mass.urdf",
       robot(link("hip_link", "2.0") + joint("thigh_joint", "revolute", "hip_link", "thigh_link") + link("thigh_link", "nan")),
       {}, {}, {"thigh_link", "mass"}, "", true});

  add({"negative_mass", "negative_mass.urdf",
       robot(link("hip_link", "2.0") + joint("thigh_joint", "revolute", "hip_link", "thigh_link") + link("thigh_link", "-1.5")),
       {}, {}, {"<link name=\"thigh_link\">", "mass", "negative"}, "", true});

  add({"missing_child_link", "orphan.urdf",
       robot(link("hip_link", "2.0") + joint("knee_joint", "revolute", "hip_link", "phantom_link")), {}, {},
       {"knee_joint", "phantom_link"}, "", true});

  add({"revolute_without_limits", "no_limits.urdf",
       robot(link("hip_link", "2.0") + joint("elbow_joint", "revolute", "hip_link", "thigh_link", false) + link("thigh_link")),
       {}, {}, {"elbow_joint", "limits"}, "", true});

  {
    UrdfOptions lock;
    lock.locked_joints["nosuchjoint"] = 0.0;
    add({"lock_nonexistent_joint", "leg.urdf", goodLeg(), {"--lock", "nosuchjoint=0"}, lock,
         {"nosuchjoint", "thigh_joint", "knee_joint"}, "", true});
  }
  {
    UrdfOptions arm;
    arm.armature["nosuchjoint"] = 0.1;
    add({"armature_nonexistent_joint", "leg.urdf", goodLeg(), {"--armature", "nosuchjoint=0.1"}, arm, {"nosuchjoint"}, "", true});
  }
  add({"massless_movable_joint", "dead.urdf",
       robot(link("hip_link", "2.0") + joint("thigh_joint", "revolute", "hip_link", "thigh_link") + link("thigh_link") +
             joint("dead_joint", "revolute", "hip_link", "ghost_link") + "  <link name=\"ghost_link\"/>\n"),
       {}, {}, {"<joint name=\"dead_joint\">", "lock", "armature"}, "", true});
  return cases;
}

class BadUrdf : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadUrdf, CliPrintsOneLineAndExitsWithOne) {
  const BadCase& c = GetParam();
  TempDir dir;
  const std::string path = c.content ? dir.write(c.file_name, *c.content) : (dir.path() / c.file_name).string();
  std::vector<std::string> args = {"inspect", path};
  args.insert(args.end(), c.options.begin(), c.options.end());
  const CliResult r = runNmdp(args, dir);
  ASSERT_TRUE(r.exited) << "nmdp was killed by a signal";
  EXPECT_EQ(r.exit_code, 1) << "stderr: " << r.err;  // not 0, not an internal error (3), not a crash (128+n)
  EXPECT_TRUE(r.out.empty()) << "nothing on stdout for bad input, got:\n" << r.out;
  expectOneLine(r.err, "stderr");
  const std::string prefix = "nmdp inspect: error: ";
  EXPECT_EQ(r.err.rfind(prefix, 0), 0u) << r.err;
  if (c.names_file) {
    EXPECT_NE(r.err.find(path), std::string::npos) << "the message must name the file: " << r.err;
  }
  for (const std::string& s : c.expect) EXPECT_NE(r.err.find(s), std::string::npos) << "missing '" << s << "' in: " << r.err;
  if (!c.line_regex.empty()) {
    // path is in a temp dir we created: no regex metacharacters other than '.' matter here.
    std::string quoted;
    for (char ch : path) quoted += std::strchr(".^$|()[]{}*+?\\", ch) ? std::string("\\") + ch : std::string(1, ch);
    EXPECT_TRUE(std::regex_search(r.err, std::regex(quoted + ":(" + c.line_regex + "):")))
        << "the message must give the line number: " << r.err;
  }
}

TEST_P(BadUrdf, LibraryThrowsInputErrorSilently) {
  const BadCase& c = GetParam();
  TempDir dir;
  const std::string path = c.content ? dir.write(c.file_name, *c.content) : (dir.path() / c.file_name).string();
  std::string message;
  bool input_error = false;
  ::testing::internal::CaptureStderr();
  ::testing::internal::CaptureStdout();
  try {
    loadUrdf(path, c.library_options);
  } catch (const InputError& e) {
    input_error = true;
    message = e.what();
  } catch (const std::exception& e) {
    message = std::string("other exception: ") + e.what();
  }
  const std::string printed_err = ::testing::internal::GetCapturedStderr();
  const std::string printed_out = ::testing::internal::GetCapturedStdout();
  ASSERT_TRUE(input_error) << "expected nmdp::InputError; " << (message.empty() ? "nothing was thrown" : message);
  EXPECT_TRUE(printed_err.empty()) << "the library must not print (urdfdom/console_bridge output leaked?):\n" << printed_err;
  EXPECT_TRUE(printed_out.empty()) << printed_out;
  EXPECT_EQ(message.find('\n'), std::string::npos) << "one-line message: " << message;
  if (c.names_file) {
    EXPECT_NE(message.find(path), std::string::npos) << message;
  }
  for (const std::string& s : c.expect) EXPECT_NE(message.find(s), std::string::npos) << "missing '" << s << "' in: " << message;
}

INSTANTIATE_TEST_SUITE_P(Cases, BadUrdf, ::testing::ValuesIn(badCases()),
                         [](const ::testing::TestParamInfo<BadCase>& info) { return info.param.name; });

// ---- option errors ------------------------------------------------------------------------------

TEST(BadInputOptions, InvalidBaseName) {
  TempDir dir;
  const std::string path = dir.write("leg.urdf", goodLeg());
  const CliResult r = runNmdp({"inspect", path, "--base", "wobbly"}, dir);
  ASSERT_TRUE(r.exited);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(r.out.empty());
  expectOneLine(r.err, "stderr");
  EXPECT_EQ(r.err.rfind("nmdp inspect: error: ", 0), 0u) << r.err;
  for (const char* s : {"--base", "wobbly", "floating", "planar", "fixed"}) EXPECT_NE(r.err.find(s), std::string::npos) << r.err;

  try {
    parseBaseType("wobbly");
    ADD_FAILURE() << "parseBaseType accepted 'wobbly'";
  } catch (const InputError& e) {
    const std::string m = e.what();
    for (const char* s : {"wobbly", "floating", "planar", "fixed"}) EXPECT_NE(m.find(s), std::string::npos) << m;
  }
}

TEST(BadInputOptions, MalformedOptionValues) {
  TempDir dir;
  const std::string path = dir.write("leg.urdf", goodLeg());
  struct Case {
    std::vector<std::string> args;
    std::vector<std::string> expect;
  };
  for (const Case& c : {Case{{"--lock", "knee_joint=abc"}, {"knee_joint=abc", "abc"}},
                        Case{{"--lock", "knee_joint"}, {"--lock", "JOINT=VALUE"}},
                        Case{{"--lock", "knee_joint=nan"}, {"knee_joint"}},
                        Case{{"--armature", "knee_joint=-1"}, {"knee_joint"}},
                        Case{{"--base"}, {"--base"}},
                        Case{{"--frobnicate"}, {"--frobnicate"}}}) {
    std::vector<std::string> args = {"inspect", path};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const CliResult r = runNmdp(args, dir);
    SCOPED_TRACE(c.args.front() + (c.args.size() > 1 ? " " + c.args[1] : ""));
    ASSERT_TRUE(r.exited);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_TRUE(r.out.empty());
    expectOneLine(r.err, "stderr");
    EXPECT_EQ(r.err.rfind("nmdp inspect: error: ", 0), 0u) << r.err;
    for (const std::string& s : c.expect) EXPECT_NE(r.err.find(s), std::string::npos) << "missing '" << s << "' in: " << r.err;
  }
}

TEST(BadInputOptions, DirectoryInsteadOfFile) {
  TempDir dir;
  const CliResult r = runNmdp({"inspect", dir.path().string()}, dir);
  ASSERT_TRUE(r.exited);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  expectOneLine(r.err, "stderr");
  EXPECT_NE(r.err.find(dir.path().string()), std::string::npos) << r.err;
  EXPECT_THROW(loadUrdf(dir.path().string()), InputError);
}

// The good fixture really is good: the bad cases fail for the reason they test.
TEST(BadInputOptions, GoodLegLoads) {
  TempDir dir;
  const std::string path = dir.write("leg.urdf", goodLeg());
  const CliResult r = runNmdp({"inspect", path, "--lock", "knee_joint=0.3", "--armature", "thigh_joint=0.01"}, dir);
  ASSERT_TRUE(r.exited);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("error"), std::string::npos) << r.err;  // warnings (e.g. about feet) are allowed
  EXPECT_NE(r.out.find("\"dof\": 7"), std::string::npos) << r.out;
  EXPECT_NO_THROW(loadUrdf(path));
}

}  // namespace
}  // namespace nmdp::test
