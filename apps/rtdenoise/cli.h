// Shared pieces of the `rtdenoise` subcommands: the exit codes, the option conventions
// (docs/cli.md) and the helpers every subcommand uses to follow them.
#pragma once
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "rtd/rtd.h"

namespace rtd::cli {

/// Exit status of every subcommand (documented in `rtdenoise --help` and docs/cli.md):
enum ExitCode : int {
  kExitOk = 0,        ///< success
  kExitBadInput = 1,  ///< bad input data or files (rtd::Error, a file-system error, out of memory): the message names file, frame, channel
  kExitUsage = 2,     ///< bad command line: unknown or meaningless option, bad value
  kExitInternal = 3,  ///< anything else: a bug in rtdenoise
};

/// A bad command line found by a subcommand after parsing: a value out of range, an unknown
/// setting, a meaningless combination of options. main() prints it and exits with kExitUsage.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The footer of `rtdenoise --help` and of every subcommand's --help.
extern const char* const kExitStatusFooter;

/// Adds a subcommand with the common footer (exit status). Every subcommand is made this way.
CLI::App* addSubcommand(CLI::App& app, const std::string& name, const std::string& description);

// Each subcommand adds itself to the app (apps/rtdenoise/cmd_<name>.cpp).
void addDenoise(CLI::App& app);
void addMethods(CLI::App& app);
void addBench(CLI::App& app);
#ifdef HAVE_RTDENOISE_EVAL
void addEval(CLI::App& app);
void addCompare(CLI::App& app);
void addDemo(CLI::App& app);
#endif
/// `render` (only when built with the renderer, HAVE_RTDENOISE_RENDER).
void addRender(CLI::App& app);
/// `dataset` (with the renderer): the learned methods' training/test data set (cmd_dataset.cpp).
void addDataset(CLI::App& app);
void addDevices(CLI::App& app);
void addPack(CLI::App& app);

/// "key=value" texts (of `--set`, or of a configuration) as assignments. UsageError naming
/// `option` on a malformed one.
std::vector<SettingAssignment> parseAssignments(const std::vector<std::string>& texts, const std::string& option = "--set");

/// Applies `--set key=value` texts to a denoiser with rtd::applySettings (presets first);
/// an unknown setting, a repeated one or a bad value is a UsageError.
void applySettings(Denoiser& d, const std::vector<std::string>& assignments);
void applySettings(StereoDenoiser& d, const std::vector<std::string>& assignments);

/// An option check: the value is a number >= `lo` (CLI11's own range message prints the type's
/// limits).
CLI::Validator atLeast(double lo);

/// The registered method `name`; UsageError naming `option` and listing the methods otherwise.
MethodInfo methodInfo(const std::string& name, const std::string& option = "--method");

/// Parses "WxH" (UsageError naming `option` otherwise).
std::pair<int, int> parseSize(const std::string& s, const std::string& option = "--size");

/// "cpu" or "vulkan" (UsageError otherwise).
Backend parseBackend(const std::string& s);

/// Splits "a,b,c" (empty items dropped).
std::vector<std::string> splitList(const std::string& s, char separator = ',');

/// `--backend`, `--device` and `--threads`, spelled and checked the same in every subcommand.
struct DeviceOptions {
  std::string backend = "cpu";
  std::string vulkanDevice;
  int threads = 0;

  /// `list`: --backend takes a comma-separated list (compare).
  void add(CLI::App* cmd, bool list = false);
  /// The backends asked for; UsageError for an unknown one, or for --device without vulkan.
  std::vector<Backend> backends() const;
  /// The one backend of a subcommand without a list (UsageError for a list).
  Backend single() const;
  DeviceDesc desc(Backend b) const { return {.backend = b, .threads = threads, .vulkanDevice = vulkanDevice}; }
};

/// `--output DIR` and `--overwrite`. prepare() makes the directory ready: created if missing;
/// if it already holds files, refused unless --overwrite, which removes the files an earlier
/// run of the same subcommand wrote there (`ours`: regular expressions on the file or
/// subdirectory name) and refuses when anything else is there, so results are never mixed
/// with an older run's and no user data is deleted.
struct OutputOptions {
  std::string dir;
  bool overwrite = false;

  void add(CLI::App* cmd, const std::string& what, bool required = true);
  void prepare(const std::vector<std::string>& ours) const;
};

/// Checks `--frames N` (0 = all) against the `available` frames; returns how many to use.
int framesToUse(int requested, int available, const std::string& option = "--frames");

/// A one-line progress display: redrawn in place on a terminal, a line every few seconds
/// otherwise (logs, CI).
class Progress {
 public:
  Progress(std::string what, int total);
  void update(int done, const std::string& detail = "");
  void finish(const std::string& detail = "");

 private:
  std::string what_;
  int total_;
  bool tty_;
  std::chrono::steady_clock::time_point start_, lastPrint_;
};

}  // namespace rtd::cli
