// Issue 21: interrupted runs leave nothing behind. About 1 in 8 runs stopped by SIGINT, SIGTERM
// or SIGKILL left a truncated `frame_NNNN.exr.tmp<pid>` beside the outputs. Here the signal is
// raised deterministically while a temporary file exists (RTD_TEST_RAISE_BEFORE_RENAME, a fault
// injection in TemporaryFile::commit): the CLI must remove it and end by the signal; files a
// killed run left are removed by the next run, those of live processes kept. Also: the CLI
// reports sanitized values per buffer, and maps errors to its exit codes.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>

#include "rtd/rtd.h"
#include "synthetic/synthetic.h"
#include "support/files.h"

namespace rtd {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> tempFiles(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().find(".tmp") != std::string::npos) out.push_back(e.path().filename().string());
  return out;
}

// Runs the CLI with `env` prepended; the raw wait status.
int runCli(const std::string& env, const std::string& args, std::string* stderrText = nullptr) {
  const fs::path log = fs::temp_directory_path() / ("rtd_interrupt_cli_" + std::to_string(::getpid()) + ".log");
  const int status = std::system((env + " " + RTD_CLI + " " + args + " > /dev/null 2> " + log.string()).c_str());
  if (stderrText) {
    std::ifstream in(log);
    *stderrText = std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  }
  fs::remove(log);
  return status;
}

TEST(InterruptedRun, SignalsRemoveTheTemporaryFile) {
  const fs::path dir = test::scratchDir("rtd_interrupt", "signal");
  test::writeSyntheticSequence(dir / "in", 3);
  for (int sig : {SIGINT, SIGTERM}) {
    const fs::path out = dir / ("out" + std::to_string(sig));
    const int status = runCli("RTD_TEST_RAISE_BEFORE_RENAME=" + std::to_string(sig),
                              "denoise -m accumulate -i " + (dir / "in").string() + " -o " + out.string());
    // std::system runs the command through sh, which reports a child killed by a signal as 128 + sig.
    const bool killed = (WIFSIGNALED(status) && WTERMSIG(status) == sig) ||
                        (WIFEXITED(status) && WEXITSTATUS(status) == 128 + sig);
    EXPECT_TRUE(killed) << "signal " << sig << ", status " << status;
    ASSERT_TRUE(fs::exists(out));
    EXPECT_EQ(tempFiles(out), std::vector<std::string>{}) << "signal " << sig;
    EXPECT_FALSE(fs::exists(out / "frame_0001.exr")) << "the interrupted write must not be renamed";
  }
  fs::remove_all(dir);
}

TEST(InterruptedRun, StaleTemporaryFilesOfDeadProcessesAreRemovedAtTheNextStart) {
  const fs::path dir = test::scratchDir("rtd_interrupt", "stale");
  test::writeSyntheticSequence(dir / "in", 2);
  const fs::path out = dir / "out";
  fs::create_directories(out);
  // A pid that no longer exists: a child that has exited and been reaped.
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ASSERT_GT(child, 0);
  ::waitpid(child, nullptr, 0);
  const std::string dead = "frame_0001.exr.tmp" + std::to_string(child);
  const std::string live = "frame_0002.exr.tmp" + std::to_string(::getppid());  // the test runner's parent is alive
  std::ofstream(out / dead) << "truncated";
  std::ofstream(out / live) << "being written";
  std::string err;
  const int status = runCli("", "denoise -m accumulate -i " + (dir / "in").string() + " -o " + out.string(), &err);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << err;
  EXPECT_EQ(tempFiles(out), std::vector<std::string>{live});
  // The library call the CLI and SequenceWriter use.
  std::ofstream(out / dead) << "truncated";
  EXPECT_EQ(removeStaleTemporaryFiles(out), 1);
  EXPECT_EQ(tempFiles(out), std::vector<std::string>{live});
  fs::remove_all(dir);
}

// timings.json and the summary line say which buffer each sanitized value came from (NaN
// depths used to be reported as "NaN/Inf/negative radiance values").
TEST(CliReport, SanitizedValuesArePerBuffer) {
  const fs::path dir = test::scratchDir("rtd_interrupt", "report");
  synthetic::Scene scene;
  scene.width = 24;
  scene.height = 16;
  {
    SequenceWriter writer(dir / "in");
    for (int k = 0; k < 2; ++k) {
      Frame f = synthetic::makeFrame(scene, k);
      if (k == 1) {
        f[Buffer::Depth].at(3, 3) = std::nanf("");
        f[Buffer::Depth].at(4, 3) = std::nanf("");
        for (int c = 0; c < 3; ++c) f[Buffer::Normal].at(5, 5, c) *= 2.0f;
      }
      writer.write(f);
    }
    writer.finish();
  }
  std::string err;
  const int status = runCli("", "denoise -m svgf -i " + (dir / "in").string() + " -o " + (dir / "out").string(), &err);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << err;
  std::ifstream in(dir / "out" / "timings.json");
  const auto t = nlohmann::json::parse(in);
  EXPECT_EQ(t["sanitizedValues"], 3);
  EXPECT_EQ(t["frames"][1]["sanitized"]["depth"]["nonFinite"], 2);
  EXPECT_EQ(t["frames"][1]["sanitized"]["normal"]["renormalized"], 1);
  EXPECT_FALSE(t["frames"][1]["sanitized"].contains("color"));
  EXPECT_NE(err.find("buffer 'depth': 2 NaN/Inf replaced by 0"), std::string::npos) << err;
  EXPECT_NE(err.find("buffer 'normal': 1 renormalized"), std::string::npos) << err;
  EXPECT_EQ(err.find("radiance"), std::string::npos) << err;
  fs::remove_all(dir);
}

// Exit codes: bad input 1 (an rtd::Error: here a corrupt file), usage 2 (an unknown option, or
// a bad value on the command line such as --set alpha=nan: docs/cli.md).
TEST(CliReport, ErrorsMapToTheDocumentedExitCodes) {
  const fs::path dir = test::scratchDir("rtd_interrupt", "codes");
  test::writeSyntheticSequence(dir / "in", 2);
  std::ofstream(dir / "in" / "frame_0002.exr", std::ios::binary) << "garbage";
  std::string err;
  int status = runCli("", "denoise -m accumulate -i " + (dir / "in").string() + " -o " + (dir / "out").string(), &err);
  EXPECT_EQ(WEXITSTATUS(status), 1) << err;
  EXPECT_NE(err.find("frame_0002.exr"), std::string::npos) << err;
  status = runCli("", "denoise -m accumulate -s alpha=nan -i " + (dir / "in").string() + " -o " + (dir / "out").string(), &err);
  EXPECT_EQ(WEXITSTATUS(status), 2) << err;
  status = runCli("", "denoise --no-such-option", &err);
  EXPECT_EQ(WEXITSTATUS(status), 2) << err;
  // An output directory that cannot be created (a file is in the way): bad input, not internal.
  std::ofstream(dir / "file") << "x";
  status = runCli("", "denoise -m accumulate -i " + (dir / "in").string() + " -o " + (dir / "file" / "out").string(), &err);
  EXPECT_EQ(WEXITSTATUS(status), 1) << err;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rtd
