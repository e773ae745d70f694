// `rtdenoise denoise`: its options, and the stereo case (`render --stereo` output: D/left, D/right).
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "cli.h"
#include "rtd/eval/compare.h"

namespace rtd::cli {

struct DenoiseOptions {
  std::string method = "svgf";
  std::string input;
  OutputOptions output;
  std::vector<std::string> settings;
  DeviceOptions device;
  int maxFrames = 0;
  bool half = false;
  bool preview = false;
  std::string toneMap = "aces";
  float exposure = 0.0f;
  SequenceOptions sequence;  // --cut, --continuous
  bool noGuideRays = false;  // --no-guide-rays: denoise the guide frames alone
  bool noPipeline = false;   // --no-pipeline: read, denoise and write each frame in turn on one thread
};

/// A directory without a sequence of its own that holds the sequences `left` and `right`.
bool isStereoSequence(const std::filesystem::path& dir);

/// Denoises both eyes with the method's two-view denoiser (rtd/stereo.h) into
/// O/left/frame_NNNN.exr and O/right/frame_NNNN.exr (and .png with --preview), and
/// O/timings.json (passes summed over the eyes, memory by category). The eyes must have the
/// same size and frame numbers; a cut in either eye resets both.
void runDenoiseStereo(const DenoiseOptions& o, const eval::ToneMapSettings& previewToneMap);

}  // namespace rtd::cli
