// How `rtdenoise denoise` reports what import sanitized (FrameStats::sanitized): per frame and
// buffer in timings.json, and one summary line naming the buffers at the end.
#pragma once
#include <array>
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

}  // namespace rtd::cli
