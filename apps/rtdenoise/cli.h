// Shared pieces of the `rtdenoise` subcommands.
#pragma once
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "rtd/rtd.h"

namespace rtd::cli {

/// Exit status of every subcommand (documented in `rtdenoise --help` and docs/cli.md):
enum ExitCode : int {
  kExitOk = 0,        ///< success
  kExitBadInput = 1,  ///< bad input data or files (rtd::Error): the message names file, frame, channel
  kExitUsage = 2,     ///< bad command line: unknown or meaningless option, bad value
  kExitInternal = 3,  ///< anything else: a bug in rtdenoise
};

// Each subcommand adds itself to the app and returns the callback that runs it.
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

/// Applies "key=value" strings to a denoiser; throws rtd::Error on a malformed one.
void applySettings(Denoiser& d, const std::vector<std::string>& assignments);
void applySettings(StereoDenoiser& d, const std::vector<std::string>& assignments);

/// Parses "WxH".
std::pair<int, int> parseSize(const std::string& s);

Backend parseBackend(const std::string& s);

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
