// Options shared by `rtdenoise eval`, `compare` and `demo`: how metrics are computed.
#pragma once
#include <CLI/CLI.hpp>
#include <algorithm>
#include <memory>
#include <string>

#include "cli.h"
#include "rtd/eval/evaluate.h"

namespace rtd::cli {

struct EvalOptions {
  std::string warmup = "auto";
  std::string toneMap = "aces";
  float exposure = 0.0f;
  std::string flip = "ldr,hdr";
  double pixelsPerDegree = 0;

  void add(CLI::App* cmd) {
    cmd->add_option("--warmup", warmup,
                    "the first N frames (history warm-up) are averaged separately; auto = min(8, frames / 4)")
        ->capture_default_str();
    cmd->add_option("--tonemap", toneMap, "tone map for the display-referred metrics: aces, reinhard or clamp")
        ->capture_default_str();
    cmd->add_option("--exposure", exposure, "exposure in stops applied before tone mapping")->capture_default_str();
    cmd->add_option("--flip", flip, "FLIP variants: ldr (tone-mapped), hdr (exposure bracket), both, or none (faster)")
        ->capture_default_str();
    cmd->add_option("--pixels-per-degree", pixelsPerDegree,
                    "FLIP viewing condition (default 67.02: a 0.7 m wide 3840-pixel monitor at 0.7 m)")
        ->check(atLeast(1));
  }

  /// The warm-up for a sequence of `frames` frames: "auto" scales with the length, an explicit
  /// N must leave at least one frame for the headline means.
  int warmupFrames(int frames) const {
    if (warmup == "auto") return std::min(8, frames / 4);
    int n = -1;
    size_t used = 0;
    try {
      n = std::stoi(warmup, &used);
    } catch (const std::exception&) {
    }
    if (used != warmup.size() || n < 0) throw UsageError("--warmup '" + warmup + "': expected auto or a number >= 0");
    if (n >= frames)
      throw UsageError("--warmup " + warmup + ": the sequence has " + std::to_string(frames) +
                       " frame(s), so no frame would be left after the warm-up");
    return n;
  }

  eval::EvalSettings settings(int frames) const {
    eval::EvalSettings s;
    s.warmupFrames = warmupFrames(frames);
    try {
      s.toneMap.op = eval::parseOperator(toneMap);
    } catch (const Error& e) {
      throw UsageError(std::string("--tonemap: ") + e.what());
    }
    s.toneMap.exposure = exposure;
    s.computeFlip = s.computeHdrFlip = false;
    for (const auto& v : splitList(flip)) {
      if (v == "ldr") s.computeFlip = true;
      else if (v == "hdr") s.computeHdrFlip = true;
      else if (v != "none") throw UsageError("--flip '" + flip + "': expected ldr, hdr, ldr,hdr or none");
    }
    if (pixelsPerDegree > 0 && !s.computeFlip && !s.computeHdrFlip)
      throw UsageError("--pixels-per-degree sets FLIP's viewing condition, but --flip is none");
    s.flip.ppd = pixelsPerDegree;
    return s;
  }
};

}  // namespace rtd::cli
