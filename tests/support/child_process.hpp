// A child process started without a shell, so that a test can signal it (SIGKILL, SIGINT) by pid.
#pragma once
#include <fcntl.h>
#include <unistd.h>

#include <string>
#include <vector>

namespace nmdp::test {

// Starts args[0] with args in a child process, stdin and stdout on /dev/null and stderr into
// `stderr_path`; returns its pid (negative if fork failed).
inline pid_t startProcess(const std::vector<std::string>& args, const std::string& stderr_path) {
  const pid_t pid = ::fork();
  if (pid != 0) return pid;
  const int null = ::open("/dev/null", O_RDWR);
  const int e = ::open(stderr_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  ::dup2(null, 0);
  ::dup2(null, 1);
  ::dup2(e, 2);
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  ::execv(argv[0], argv.data());
  ::_exit(127);
}

}  // namespace nmdp::test
