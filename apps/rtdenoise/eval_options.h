// Options shared by `rtdenoise eval`, `compare` and `demo`: how metrics are computed.
#pragma once
#include <CLI/CLI.hpp>
#include <memory>
#include <string>

#include "rtd/eval/evaluate.h"

namespace rtd::cli {

struct EvalOptions {
  int warmup = 8;
  std::string toneMap = "aces";
  float exposure = 0.0f;
  bool noFlip = false;

  void add(CLI::App* cmd) {
    cmd->add_option("--warmup", warmup, "first N frames are averaged separately (history warm-up)")->capture_default_str();
    cmd->add_option("--tonemap", toneMap, "tone map for the display-referred metrics: aces, reinhard or clamp")
        ->capture_default_str();
    cmd->add_option("--exposure", exposure, "exposure in stops applied before tone mapping")->capture_default_str();
    cmd->add_flag("--no-flip", noFlip, "skip FLIP (faster)");
  }
  eval::EvalSettings settings() const {
    eval::EvalSettings s;
    s.warmupFrames = warmup;
    s.toneMap.op = eval::parseOperator(toneMap);
    s.toneMap.exposure = exposure;
    s.computeFlip = !noFlip;
    if (warmup < 0) throw Error("--warmup " + std::to_string(warmup) + ": must be >= 0");
    return s;
  }
};

}  // namespace rtd::cli
