// Runs the `rtdenoise` command built with the tests (RTD_CLI) and captures what it prints.
#pragma once
#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace rtd::test {

struct CliResult {
  int code;            ///< exit status (-1 if it did not exit normally)
  std::string output;  ///< standard output and standard error together
};

inline CliResult runCli(const std::string& args) {
  const std::string cmd = std::string(RTD_CLI) + " " + args + " 2>&1";
  FILE* p = ::popen(cmd.c_str(), "r");
  std::string out;
  char buf[4096];
  while (size_t n = std::fread(buf, 1, sizeof buf, p)) out.append(buf, n);
  const int status = ::pclose(p);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

}  // namespace rtd::test
