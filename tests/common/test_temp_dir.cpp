// The tests' temporary folders (tests/support/test_temp_dir.hpp): named after the running test
// executable, so that a folder left behind by a killed test says which one it was.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "test_temp_dir.hpp"

namespace nmdp {
namespace {

using test::TempDir;

TEST(TempDir, IsNamedAfterTheTestExecutableAndProcess) {
  TempDir dir;
  const std::string name = dir.path().filename().string();
  const std::string prefix = "nmdp_test_temp_dir_" + std::to_string(::getpid()) + "_";
  EXPECT_EQ(name.rfind(prefix, 0), 0u) << name;
  EXPECT_TRUE(std::filesystem::is_directory(dir.path()));
}

TEST(TempDir, IsRemovedWithItsFilesAtScopeExit) {
  std::filesystem::path path;
  {
    TempDir dir;
    path = dir.path();
    dir.write("sub/a.txt", "x");
    ASSERT_TRUE(std::filesystem::exists(path / "sub" / "a.txt"));
  }
  EXPECT_FALSE(std::filesystem::exists(path));
}

}  // namespace
}  // namespace nmdp
