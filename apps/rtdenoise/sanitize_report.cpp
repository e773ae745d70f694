#include "sanitize_report.h"

namespace rtd::cli {

nlohmann::json sanitizeJson(const BufferCounts& counts) {
  nlohmann::json j = nlohmann::json::object();
  for (int b = 0; b < kBufferCount; ++b) {
    const SanitizeCounts& c = counts[size_t(b)];
    if (c.total() == 0) continue;
    j[std::string(bufferName(Buffer(b)))] = {
        {"nonFinite", c.nonFinite}, {"outOfRange", c.outOfRange}, {"renormalized", c.renormalized}};
  }
  return j;
}

void accumulate(BufferCounts& total, const BufferCounts& frame) {
  for (size_t b = 0; b < total.size(); ++b) {
    total[b].nonFinite += frame[b].nonFinite;
    total[b].outOfRange += frame[b].outOfRange;
    total[b].renormalized += frame[b].renormalized;
  }
}

std::string sanitizeSummary(const BufferCounts& counts) {
  std::string out;
  for (int b = 0; b < kBufferCount; ++b) {
    const SanitizeCounts& c = counts[size_t(b)];
    if (c.total() == 0) continue;
    std::string parts;
    auto add = [&](uint64_t n, const char* what) {
      if (n) parts += (parts.empty() ? "" : ", ") + std::to_string(n) + " " + what;
    };
    add(c.nonFinite, "NaN/Inf replaced by 0");
    add(c.outOfRange, "clamped into range");
    add(c.renormalized, "renormalized");
    out += (out.empty() ? "" : "; ") + std::string("buffer '") + std::string(bufferName(Buffer(b))) + "': " + parts;
  }
  return out;
}

}  // namespace rtd::cli
