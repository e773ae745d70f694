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

/// Runs the shell command line `cmd` and captures its standard output.
inline CliResult runCommand(const std::string& cmd) {
  FILE* p = ::popen(cmd.c_str(), "r");
  std::string out;
  char buf[4096];
  while (size_t n = std::fread(buf, 1, sizeof buf, p)) out.append(buf, n);
  const int status = ::pclose(p);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

/// The command line `rtdenoise <args><redirection>`, appended piece by piece (on a chain of
/// operator+ over temporaries GCC 12 warns wrongly that std::string's memcpy overruns,
/// -Warray-bounds).
inline std::string cliCommand(const std::string& args, const char* redirection) {
  std::string cmd = RTD_CLI;
  cmd += ' ';
  cmd += args;
  cmd += redirection;
  return cmd;
}

/// `rtdenoise <args>`: its exit status, and standard output and error together.
inline CliResult runCli(const std::string& args) { return runCommand(cliCommand(args, " 2>&1")); }

/// `rtdenoise <args>`: its exit status and standard error (standard output is discarded).
inline CliResult runCliStderr(const std::string& args) { return runCommand(cliCommand(args, " 2>&1 > /dev/null")); }

}  // namespace rtd::test
