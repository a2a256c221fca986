// nmdp view on bad input: one message naming the file and the dataset, exit 1 (no page written);
// no run: usage, exit 2; the page is never written over a file nmdp did not write. A contact name
// holding "</script>" cannot end the payload's element. --serve 0 answers a GET with the page and
// ends on SIGTERM with exit 0.
#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <regex>
#include <thread>

#include "run_file_edits.hpp"
#include "run_files.hpp"
#include "simulate_run.hpp"
#include "test_cli.hpp"
#include "test_support.hpp"
#include "view_page.hpp"

namespace nmdp::test {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

// One short run, copied for each case to damage.
class ViewErrors : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    run_dir_ = new TempDir();
    run_ = run_dir_->file("trot.h5");
    runComplete({trotScene(), "--set", "duration=0.2", "--quiet"}, *run_dir_, run_);
  }
  static void TearDownTestSuite() {
    delete run_dir_;
    run_dir_ = nullptr;
  }
  std::string copyOfRun(const std::string& name) {
    const std::string copy = dir_.file(name);
    fs::copy_file(run_, copy, fs::copy_options::overwrite_existing);
    return copy;
  }
  // nmdp view must fail with exit 1 and one line naming `file` and containing each of `words`, and
  // write no page.
  void expectRefused(const std::vector<std::string>& args, const std::string& file, const std::vector<std::string>& words) {
    const std::string page = dir_.file("refused.html");
    std::vector<std::string> full = args;
    full.insert(full.end(), {"--out", page});
    const CliResult r = runView(full, dir_);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    ASSERT_NO_FATAL_FAILURE(expectOneLine(r.err, "stderr"));
    EXPECT_EQ(r.err.rfind("nmdp view: error: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(file), std::string::npos) << "the message does not name " << file << ": " << r.err;
    for (const std::string& w : words) EXPECT_NE(r.err.find(w), std::string::npos) << "'" << w << "' not in: " << r.err;
    EXPECT_FALSE(fs::exists(page));
  }
  TempDir dir_;
  static TempDir* run_dir_;
  static std::string run_;
};
TempDir* ViewErrors::run_dir_ = nullptr;
std::string ViewErrors::run_;

TEST_F(ViewErrors, BadInputsAreOneMessageNamingTheFileAndTheDataset) {
  useStandInBundle(dir_);
  ASSERT_TRUE(fs::exists(run_));
  const std::string text = dir_.file("notes.txt");
  std::ofstream(text) << "not HDF5\n";
  expectRefused({text}, text, {"not an HDF5 file"});
  expectRefused({dir_.file("absent.h5")}, dir_.file("absent.h5"), {});

  const std::string foreign = copyOfRun("foreign.h5");
  EditedRun(foreign).removeRootAttribute("nmdp_output");
  expectRefused({foreign}, foreign, {"nmdp_output"});

  const std::string empty = copyOfRun("empty.h5");
  EditedRun(empty).overwrite("/rows", {0.0});
  EditedRun(empty).overwrite("/steps", {0.0});
  expectRefused({empty}, empty, {"no rows"});

  const std::string bad_q = copyOfRun("bad_q.h5");
  const long rows = completeRows(run_);
  EditedRun(bad_q).setNumbers("/q", {static_cast<hsize_t>(rows), 5}, std::vector<double>(rows * 5, 0.0));
  expectRefused({bad_q}, bad_q, {"'/q'", "shape"});

  const std::string nan_time = copyOfRun("nan_time.h5");
  {
    std::vector<double> time(static_cast<size_t>(rows));
    for (long i = 0; i < rows; ++i) time[i] = 0.05 * i;
    time[2] = std::numeric_limits<double>::quiet_NaN();
    EditedRun(nan_time).overwrite("/time", time);
  }
  expectRefused({nan_time}, nan_time, {"'/time'", "not finite", "row 2"});

  // A good run after a bad one: still refused, naming the bad one.
  expectRefused({run_, nan_time}, nan_time, {"'/time'"});
}

TEST_F(ViewErrors, MissingBundleNoRunAndForeignOutputs) {
  const std::string gone = dir_.file("no-such-bundle.js");
  ::setenv("NMDP_VIEWER_BUNDLE", gone.c_str(), 1);
  expectRefused({run_}, gone, {"scripts/build.sh"});

  useStandInBundle(dir_);
  const CliResult none = runView({}, dir_);
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_NE(none.err.find("usage: nmdp view"), std::string::npos) << none.err;

  // A file nmdp did not write is never replaced; nor is the run itself.
  const std::string mine = dir_.file("mine.html");
  std::ofstream(mine) << "<html>my notes</html>\n";
  const CliResult foreign = runView({run_, "--out", mine}, dir_);
  EXPECT_EQ(foreign.exit_code, 1);
  EXPECT_NE(foreign.err.find("not one nmdp wrote"), std::string::npos) << foreign.err;
  EXPECT_EQ(readText(mine), "<html>my notes</html>\n");
  const CliResult onto_run = runView({run_, "--out", run_}, dir_);
  EXPECT_EQ(onto_run.exit_code, 1);
  EXPECT_NE(onto_run.err.find("a run to show"), std::string::npos) << onto_run.err;
  EXPECT_EQ(statusOf(run_), "complete");
}

TEST_F(ViewErrors, ScriptEndInAStringCannotBreakThePage) {
  useStandInBundle(dir_);
  const std::string run = copyOfRun("names.h5");
  const std::string hostile = "FL</script><script>document.title='owned'</script>";
  {
    EditedRun edit(run);
    edit.setStrings("/contacts/names", {hostile, "FR</SCRIPT>", "RL", "RR"});
  }
  const std::string page_path = dir_.file("names.html");
  const CliResult r = runView({run, "--out", page_path, "--quiet"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string html = readText(page_path);
  // Exactly the two elements end: the payload's and the script's.
  size_t ends = 0;
  std::string lower = html;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (size_t at = lower.find("</script"); at != std::string::npos; at = lower.find("</script", at + 1)) ++ends;
  EXPECT_EQ(ends, 2u) << "a string ended an element early";
  const json p = payloadOf(html);
  EXPECT_EQ(p["runs"][0]["contacts"]["names"][0], hostile);
  EXPECT_EQ(p["runs"][0]["contacts"]["names"][1], "FR</SCRIPT>");
}

// GET / from 127.0.0.1:port: the whole response (headers and body).
std::string httpGet(int port, const std::string& target) {
  const int s = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  address.sin_port = htons(static_cast<uint16_t>(port));
  if (::connect(s, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    ::close(s);
    return "";
  }
  const std::string request = "GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n";
  ::send(s, request.data(), request.size(), MSG_NOSIGNAL);
  std::string response;
  char buffer[65536];
  ssize_t n;
  while ((n = ::recv(s, buffer, sizeof buffer, 0)) > 0) response.append(buffer, static_cast<size_t>(n));
  ::close(s);
  return response;
}

TEST_F(ViewErrors, ServeAnswersAGetWithThePageUntilSigterm) {
  useStandInBundle(dir_);
  const std::string page = dir_.file("served.html"), out = dir_.file("serve_stdout.txt");
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int fd = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = ::open((out + ".err").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(fd, 1);
    ::dup2(err, 2);
    ::execl(NMDP_BINARY, NMDP_BINARY, "view", run_.c_str(), "--out", page.c_str(), "--serve", "0", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ASSERT_GT(pid, 0);
  int port = 0;
  const std::regex address(R"(serving .* on http://127\.0\.0\.1:(\d+)/)");
  const auto start = std::chrono::steady_clock::now();
  while (port == 0 && std::chrono::steady_clock::now() - start < std::chrono::seconds(30)) {
    std::smatch m;
    const std::string text = readText(out);
    if (std::regex_search(text, m, address)) port = std::stoi(m[1]);
    else std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  std::string response, missing;
  if (port > 0) {
    response = httpGet(port, "/");
    missing = httpGet(port, "/other");
  }
  ::kill(pid, SIGTERM);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_GT(port, 0) << "no address printed: " << readText(out);
  EXPECT_NE(readText(out).find("wrote " + page + " (1 run, 5 frames)"), std::string::npos) << readText(out);
  EXPECT_EQ(response.rfind("HTTP/1.1 200 OK\r\n", 0), 0u) << response.substr(0, 200);
  const size_t body = response.find("\r\n\r\n");
  ASSERT_NE(body, std::string::npos);
  EXPECT_EQ(response.substr(body + 4), readText(page)) << "the body is not the page";
  EXPECT_NE(response.find("Content-Type: text/html"), std::string::npos);
  EXPECT_EQ(missing.rfind("HTTP/1.1 404", 0), 0u) << missing.substr(0, 200);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "SIGTERM must end the server with exit 0";
}

}  // namespace
}  // namespace nmdp::test
