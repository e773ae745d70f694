#include "sanitize_report.h"

#include <algorithm>
#include <cstdio>

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

void TimingLog::add(nlohmann::json entry, const FrameStats& st, bool cut) {
  entry["totalMs"] = st.totalMilliseconds;
  entry["sanitizedValues"] = st.sanitizedValues;
  entry["sanitized"] = sanitizeJson(st.sanitized);
  if (cut) entry["cut"] = true;
  if (!st.notes.empty()) entry["notes"] = st.notes;
  frames_.push_back(std::move(entry));
  for (const auto& n : st.notes)
    if (std::find(notes_.begin(), notes_.end(), n) == notes_.end()) notes_.push_back(n);
  sanitized_ += st.sanitizedValues;
  accumulate(sanitizedPerBuffer_, st.sanitized);
  totals_.push_back(st.totalMilliseconds);
}

void TimingLog::write(const std::filesystem::path& dir, bool half) {
  std::vector<double> sorted = totals_;
  std::sort(sorted.begin(), sorted.end());
  timing["frames"] = frames_;
  timing["pixels"] = half ? "half" : "float";
  timing["medianTotalMs"] = sorted.empty() ? 0.0 : sorted[sorted.size() / 2];
  timing["sanitizedValues"] = sanitized_;
  timing["sanitized"] = sanitizeJson(sanitizedPerBuffer_);
  timing["notes"] = notes_;
  writeFileAtomic(dir / "timings.json", timing.dump(1));
  if (sanitized_)
    std::fprintf(stderr, "note: %llu input values were sanitized: %s (see timings.json)\n", (unsigned long long)sanitized_,
                 sanitizeSummary(sanitizedPerBuffer_).c_str());
  for (const auto& n : notes_) std::fprintf(stderr, "note: %s\n", n.c_str());
}

}  // namespace rtd::cli
