// `rtdenoise denoise` on a stereo sequence (`render --stereo` output: D/left, D/right).
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace rtd::cli {

struct DenoiseOptions {
  std::string method = "svgf";
  std::string input, output;
  std::vector<std::string> settings;
  std::string backend = "cpu";
  std::string vulkanDevice;
  int threads = 0;
  int maxFrames = 0;
};

/// A directory without a sequence of its own that holds the sequences `left` and `right`.
bool isStereoSequence(const std::filesystem::path& dir);

/// Denoises both eyes with the method's two-view denoiser (rtd/stereo.h) into
/// O/left/frame_NNNN.exr and O/right/frame_NNNN.exr, and O/timings.json (passes summed over
/// the eyes, memory by category). The eyes must have the same size and frame numbers.
void runDenoiseStereo(const DenoiseOptions& o);

}  // namespace rtd::cli
