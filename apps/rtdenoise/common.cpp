#include <unistd.h>

#include <cmath>
#include <cstdio>

#include "cli.h"

namespace rtd::cli {

namespace {
template <class D> void applyAssignments(D& d, const std::vector<std::string>& assignments) {
  for (const auto& a : assignments) {
    const auto eq = a.find('=');
    if (eq == std::string::npos || eq == 0) throw Error("--set '" + a + "': expected key=value");
    d.set(a.substr(0, eq), a.substr(eq + 1));
  }
}
}  // namespace

void applySettings(Denoiser& d, const std::vector<std::string>& assignments) { applyAssignments(d, assignments); }
void applySettings(StereoDenoiser& d, const std::vector<std::string>& assignments) { applyAssignments(d, assignments); }

std::pair<int, int> parseSize(const std::string& s) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(s.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') || w <= 0 || h <= 0 ||
      w > 16384 || h > 16384)
    throw Error("size '" + s + "': expected WIDTHxHEIGHT, e.g. 1280x720");
  return {w, h};
}

Backend parseBackend(const std::string& s) {
  if (s == "cpu") return Backend::Cpu;
  if (s == "vulkan") return Backend::Vulkan;
  throw Error("backend '" + s + "': expected cpu or vulkan");
}

Progress::Progress(std::string what, int total)
    : what_(std::move(what)), total_(total), tty_(::isatty(STDERR_FILENO)),
      start_(std::chrono::steady_clock::now()), lastPrint_(start_) {}

void Progress::update(int done, const std::string& detail) {
  const auto now = std::chrono::steady_clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  if (!tty_ && std::chrono::duration<double>(now - lastPrint_).count() < 5.0 && done != total_) return;
  lastPrint_ = now;
  const double eta = done > 0 ? elapsed / done * (total_ - done) : 0.0;
  const int width = 30, filled = total_ > 0 ? width * done / total_ : width;
  std::string bar(size_t(filled), '#');
  bar.resize(width, '.');
  std::fprintf(stderr, "%s%s [%s] %d/%d  %.1fs elapsed, ETA %.1fs  %s%s", tty_ ? "\r\033[K" : "", what_.c_str(),
               bar.c_str(), done, total_, elapsed, eta, detail.c_str(), tty_ ? "" : "\n");
  std::fflush(stderr);
}

void Progress::finish(const std::string& detail) {
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::fprintf(stderr, "%s%s: %d/%d done in %.1fs %s\n", tty_ ? "\r\033[K" : "", what_.c_str(), total_, total_,
               elapsed, detail.c_str());
}

}  // namespace rtd::cli
