// How `rtdenoise denoise` reports what import sanitized (FrameStats::sanitized): per frame and
// buffer in timings.json, and one summary line naming the buffers at the end.
#pragma once
#include <array>
#include <filesystem>
#include <vector>
#include <nlohmann/json.hpp>
#include <string>

#include "rtd/rtd.h"

namespace rtd::cli {

using BufferCounts = std::array<SanitizeCounts, kBufferCount>;

/// {"color": {"nonFinite": 2, "outOfRange": 1, "renormalized": 0}, ...}: buffers with no
/// replaced value are left out.
nlohmann::json sanitizeJson(const BufferCounts& counts);

/// Adds one frame's counts to `total`.
void accumulate(BufferCounts& total, const BufferCounts& frame);

/// "buffer 'color': 3 NaN/Inf replaced by 0, 4 clamped into range; buffer 'normal': 6
/// renormalized" or empty when nothing was replaced.
std::string sanitizeSummary(const BufferCounts& counts);

/// The per-frame log `denoise` writes as timings.json (mono and stereo): each frame's entry, the
/// sanitized values per buffer, the distinct notes (parts that did not run) and the median total.
struct TimingLog {
  nlohmann::json timing = nlohmann::json::object();  // the run's description; add() and write() fill the rest
  /// Records frame `entry` (the caller's fields) with st's sanitize counts, notes and total.
  void add(nlohmann::json entry, const FrameStats& st, bool cut);
  /// Writes <dir>/timings.json atomically, then the sanitize summary and the notes to stderr.
  void write(const std::filesystem::path& dir, bool half);

 private:
  nlohmann::json frames_ = nlohmann::json::array();
  std::vector<std::string> notes_;
  std::vector<double> totals_;
  uint64_t sanitized_ = 0;
  BufferCounts sanitizedPerBuffer_{};
};

}  // namespace rtd::cli
