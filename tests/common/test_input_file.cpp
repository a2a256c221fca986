// Reading user files and JSON text (src/common): every refusal is one InputError naming the file,
// before anything unbounded is read or parsed.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <string>

#include "common/input_error.hpp"
#include "common/input_file.hpp"
#include "common/json_text.hpp"
#include "test_temp_dir.hpp"

namespace nmdp {
namespace {

using test::TempDir;

std::string messageOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

TEST(InputFile, ReadsARegularFile) {
  TempDir dir;
  const std::string path = dir.write("a.txt", std::string("x\0y", 3));
  EXPECT_EQ(readInputFile(path, "test file"), std::string("x\0y", 3));
  EXPECT_NO_THROW(requireRegularFile(path, "test file"));
}

TEST(InputFile, RefusesWhatIsNotARegularFileBeforeReadingIt) {
  TempDir dir;
  EXPECT_EQ(messageOf([&] { readInputFile(dir.file("missing.json"), "scene file"); }),
            dir.file("missing.json") + ": cannot read the scene file: no such file");
  EXPECT_EQ(messageOf([&] { readInputFile(dir.dir(), "scene file"); }),
            dir.dir() + ": cannot read the scene file: it is a folder, not a file");
  // Devices would be read without end (/dev/zero, /dev/urandom) or block (a pipe).
  for (const char* device : {"/dev/zero", "/dev/urandom", "/dev/null"})
    EXPECT_EQ(messageOf([&] { readInputFile(device, "URDF file"); }),
              std::string(device) + ": cannot read the URDF file: it is not a regular file (a device, pipe or socket)");
  const std::string fifo = dir.file("pipe");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_NE(messageOf([&] { readInputFile(fifo, "URDF file"); }).find("not a regular file"), std::string::npos);
  const std::string file = dir.write("f", "abc");
  EXPECT_EQ(messageOf([&] { readInputFile(file + "/inside", "URDF file"); }),
            file + "/inside: cannot read the URDF file: a component of the path is not a folder");
}

TEST(InputFile, RefusesAFileLargerThanItsLimit) {
  TempDir dir;
  const std::string path = dir.write("big.csv", std::string(2048, 'x'));
  EXPECT_EQ(readInputFile(path, "CSV file", 2048).size(), 2048u);
  EXPECT_NE(messageOf([&] { readInputFile(path, "CSV file", 2047); }).find("more than the"), std::string::npos);
}

TEST(InputFile, AbsurdPathsGiveOneShortMessage) {
  const std::string long_path = "/tmp/" + std::string(100000, 'a') + ".urdf";
  const std::string message = messageOf([&] { readInputFile(long_path, "URDF file"); });
  EXPECT_NE(message.find("more than the 4096 a path may have"), std::string::npos) << message;
  EXPECT_LT(message.size(), 500u);
  EXPECT_NE(message.find("characters)..."), std::string::npos);
  EXPECT_EQ(messageOf([&] { readInputFile("", "URDF file"); }), ": cannot read the URDF file: the path is empty");
  EXPECT_FALSE(pathExists(long_path));
  EXPECT_FALSE(pathExists(""));
  EXPECT_TRUE(pathExists("/tmp"));
  // One name longer than NAME_MAX within a short path.
  const std::string long_name = "/tmp/" + std::string(300, 'b');
  EXPECT_NE(messageOf([&] { readInputFile(long_name, "URDF file"); }).find("too long"), std::string::npos);
}

TEST(JsonText, ParsesAndReportsLineAndColumn) {
  EXPECT_EQ(parseJson("{\"a\": [1, 2]}", "s.json")["a"][1], 2);
  const std::string message = messageOf([] { parseJson("{\n  \"a\": 1,\n  \"b\" 2\n}", "s.json"); });
  EXPECT_EQ(message.rfind("s.json:3:", 0), 0u) << message;
  EXPECT_NE(message.find("invalid JSON"), std::string::npos);
}

TEST(JsonText, RefusesDeepNestingBeforeParsing) {
  const int n = 100000;
  const std::string deep = std::string(n, '[') + std::string(n, ']');
  const std::string message = messageOf([&] { parseJson(deep, "k.json"); });
  EXPECT_EQ(message, "k.json:1:65: invalid JSON: nested more than 64 levels deep");
  EXPECT_FALSE(isJson(deep));
  // Brackets inside strings do not count.
  const std::string quoted = "\"" + std::string(1000, '[') + "\\\"" + "\"";
  EXPECT_TRUE(parseJson(quoted, "q").is_string());
  const std::string ok = std::string(64, '[') + std::string(64, ']');
  EXPECT_NO_THROW(parseJson(ok, "ok"));
}

TEST(JsonText, AKeyGivenTwiceInOneObjectIsRefused) {
  EXPECT_EQ(messageOf([] { parseJson("{\"duration\": 1, \"robot\": {}, \"duration\": 2}", "s.json"); }),
            "s.json: invalid JSON: the key \"duration\" appears twice in one object");
  EXPECT_NE(messageOf([] { parseOrderedJson("{\"a\": {\"b\": 1, \"b\": 1}}", "o.json"); }).find("\"b\" appears twice"),
            std::string::npos);
  // The same key in two objects, or in an object within an array, is no duplicate.
  EXPECT_NO_THROW(parseJson("{\"a\": {\"k\": 1}, \"b\": {\"k\": 2}, \"c\": [{\"k\": 1}, {\"k\": 2}]}", "ok"));
}

TEST(JsonText, NumberOverflowIsAnInputError) {
  const std::string message = messageOf([] { parseJson("1e309", "--set duration=1e309"); });
  EXPECT_EQ(message.rfind("--set duration=1e309: invalid JSON: number overflow", 0), 0u) << message;
  EXPECT_TRUE(isJson("1e309"));  // syntactically JSON: parseJson then says why it cannot be read
}

TEST(JsonText, MessagesShowValuesShortAndNeverThrow) {
  nlohmann::json big = nlohmann::json::array();
  for (int i = 0; i < 10000; ++i) big.push_back(i);
  const std::string shown = jsonForMessage(big);
  EXPECT_EQ(shown.size(), 83u);
  EXPECT_EQ(shown.substr(80), "...");
  const nlohmann::json bad_utf8 = std::string("\xff\xfe");
  EXPECT_NO_THROW(jsonForMessage(bad_utf8));
}

}  // namespace
}  // namespace nmdp
