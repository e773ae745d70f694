// A soak: a long stream of small renderer-made frames with camera cuts, resizes and bad
// pixels injected, through each method on each backend, with the resident memory sampled and
// every output checked. bench/soak/soak_main.cpp runs it at length (scripts/soak.sh: 1000
// frames per method per backend); tests/reliability/soak_test.cpp runs a short version.
#pragma once
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "rtd/render/render.h"
#include "rtd/rtd.h"

namespace rtd::soak {

struct Config {
  int frames = 1000;                 ///< per method and backend
  std::vector<std::string> methods;  ///< empty: every method the backend has
  std::vector<Backend> backends{Backend::Cpu, Backend::Vulkan};
  /// The stream is a series of shots of `shotLength` frames, each a camera cut to the other
  /// scene (from its first frame); the image size changes every `shotsPerSize` shots (a resize).
  int shotLength = 100;
  int shotsPerSize = 2;
  std::vector<std::pair<int, int>> sizes{{64, 48}, {48, 32}};
  std::vector<std::string> scenes{"cornell", "pillars"};
  /// Frame `badAt` of every shot has bad pixels: NaN, Inf and negative radiance, non-unit and
  /// NaN normals, NaN and huge depths and motion, and with `fireflies` 1e30 radiance too
  /// (clamped to kMaxRadiance on import: a firefly that then decays in history).
  int badAt = 5;
  bool fireflies = true;
  /// From frame `checkFrom` of a shot on, a frame is "stable" when its mean output is within
  /// [1/maxMeanRatio, maxMeanRatio] of its clean input's mean. 65 frames after a kMaxRadiance
  /// firefly, BMFR's phase III history (weight 0.1 per frame) still holds 0.9^65 = 0.1% of it:
  /// 3 such pixels add ~0.2 to the mean of a 64x48 frame of mean 0.1-0.3.
  int checkFrom = 70;
  double maxMeanRatio = 2.0;
  /// Resident memory is sampled every `rssEvery` frames; after the first `warmupFrames` (every
  /// size, cut and bad frame seen), it may not grow by more than `rssBoundMiB`.
  int rssEvery = 25;
  int warmupFrames = 300;
  double rssBoundMiB = 24;
  std::function<void(const std::string&)> log = [](const std::string&) {};
};

struct Result {
  std::string method;
  Backend backend = Backend::Cpu;
  int frames = 0;
  int nonFiniteFrames = 0;  ///< frames with any non-finite output value
  int unstableFrames = 0;   ///< checked frames whose mean left the allowed ratio
  int checkedFrames = 0;
  double rssBaselineMiB = 0, rssMaxMiB = 0, rssEndMiB = 0;
  double seconds = 0;
  std::string error;  ///< an exception's message, if the run stopped
  bool memoryOk(double boundMiB) const { return rssMaxMiB - rssBaselineMiB <= boundMiB; }
  bool ok(double boundMiB) const { return error.empty() && nonFiniteFrames == 0 && unstableFrames == 0 && memoryOk(boundMiB); }
};

/// Resident set size of this process in MiB (/proc/self/statm).
inline double residentMiB() {
  std::ifstream in("/proc/self/statm");
  long pages = 0, resident = 0;
  in >> pages >> resident;
  return double(resident) * double(::sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

/// The rendered frames the stream is made of: for each scene and size, `shotLength` consecutive
/// frames (a shot starts a scene at its first frame, so these are all the stream needs).
class FramePool {
 public:
  explicit FramePool(const Config& c) : c_(c) {
    for (const auto& name : c.scenes) {
      auto scene = render::Scene::load(name);
      for (const auto& [w, h] : c.sizes) {
        render::RenderSettings s = scene->suggestedSettings();
        s.width = w;
        s.height = h;
        s.spp = 1;
        render::Renderer r(scene, s);
        std::vector<Frame> frames;
        for (int k = 0; k < c.shotLength; ++k) frames.push_back(r.render(k % std::max(1, scene->frameCount())));
        pool_.push_back(std::move(frames));
      }
    }
  }
  /// Frame `i` of the stream; `k` receives its index in its shot (0: a cut).
  const Frame& at(int i, int* k) const {
    const int shot = i / c_.shotLength;
    *k = i % c_.shotLength;
    const size_t scene = size_t(shot) % c_.scenes.size();
    const size_t size = size_t(shot / c_.shotsPerSize) % c_.sizes.size();
    return pool_[scene * c_.sizes.size() + size][size_t(*k)];
  }

 private:
  const Config& c_;
  std::vector<std::vector<Frame>> pool_;
};

/// Writes bad values into 24 pixels of `f`, of every kind in turn (1e30 radiance only with
/// `fireflies`).
inline void injectBadPixels(Frame& f, uint32_t seed, bool fireflies) {
  std::mt19937 rng(seed);
  const float nan = std::nanf(""), inf = INFINITY;
  for (int k = 0; k < 24; ++k) {
    const int x = int(rng() % uint32_t(f.width)), y = int(rng() % uint32_t(f.height));
    switch (k % 8) {
      case 0: f[Buffer::Color].at(x, y, 0) = nan; break;
      case 1: f[Buffer::Color].at(x, y, 1) = inf; break;
      case 2: for (int c = 0; c < 3; ++c) f[Buffer::Color].at(x, y, c) = fireflies ? 1e30f : -1e30f; break;
      case 3: f[Buffer::Color].at(x, y, 2) = -5.0f; break;
      case 4: if (f.has(Buffer::Normal)) for (int c = 0; c < 3; ++c) f[Buffer::Normal].at(x, y, c) *= (k & 8) ? 1e10f : 1.5f; break;
      case 5: if (f.has(Buffer::Normal)) f[Buffer::Normal].at(x, y, 1) = nan; break;
      case 6: if (f.has(Buffer::Depth)) f[Buffer::Depth].at(x, y) = (k & 8) ? nan : 3e38f; break;
      default: if (f.has(Buffer::Motion)) f[Buffer::Motion].at(x, y, 0) = (k & 8) ? 1e30f : nan; break;
    }
  }
}

inline double meanOf(const Image& img, int channels) {
  double s = 0;
  for (size_t i = 0; i < size_t(img.width) * img.height; ++i)
    for (int c = 0; c < channels; ++c) s += img.pixels[i * size_t(img.channels) + size_t(c)];
  return s / (double(img.width) * img.height * channels);
}

/// Runs one method on one device over the stream.
inline Result runOne(const Config& c, const FramePool& pool, Device& device, const std::string& method) {
  Result r;
  r.method = method;
  r.backend = device.backend();
  const auto start = std::chrono::steady_clock::now();
  try {
    auto d = device.createDenoiser(method);
    Image out;
    for (int i = 0; i < c.frames; ++i) {
      int k = 0;
      const Frame& clean = pool.at(i, &k);
      Frame f = clean;
      if (k == c.badAt) injectBadPixels(f, uint32_t(i), c.fireflies);
      if (out.width != f.width || out.height != f.height) out = Image(f.width, f.height, 3);
      FrameInputs in = f.inputs();
      in.cameraCut = k == 0;
      d->denoise(in, out.view());
      bool finite = true;
      for (float v : out.pixels) finite = finite && std::isfinite(v);
      r.nonFiniteFrames += !finite;
      if (finite && k >= c.checkFrom) {
        const double ratio = meanOf(out, 3) / std::max(1e-6, meanOf(clean[Buffer::Color], 3));
        r.unstableFrames += !(ratio <= c.maxMeanRatio && ratio >= 1.0 / c.maxMeanRatio);
        ++r.checkedFrames;
      }
      ++r.frames;
      if (i % c.rssEvery == 0 || i + 1 == c.frames) {
        const double rss = residentMiB();
        if (i < c.warmupFrames) r.rssBaselineMiB = std::max(r.rssBaselineMiB, rss);
        else r.rssMaxMiB = std::max(r.rssMaxMiB, rss);
        r.rssEndMiB = rss;
      }
    }
  } catch (const std::exception& e) {
    r.error = e.what();
  }
  if (r.rssMaxMiB == 0) r.rssMaxMiB = r.rssBaselineMiB;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  char line[256];
  std::snprintf(line, sizeof line,
                "%-10s %-6s %5d frames %7.1f s  RSS %.1f -> max %.1f MiB (end %.1f)  non-finite %d  unstable %d/%d%s%s",
                method.c_str(), std::string(backendName(r.backend)).c_str(), r.frames, r.seconds, r.rssBaselineMiB,
                r.rssMaxMiB, r.rssEndMiB, r.nonFiniteFrames, r.unstableFrames, r.checkedFrames,
                r.error.empty() ? "" : "  ERROR: ", r.error.c_str());
  c.log(line);
  return r;
}

/// Every configured method on every configured backend (a backend that cannot be created is
/// reported as an error result).
inline std::vector<Result> run(const Config& c) {
  const FramePool pool(c);
  std::vector<Result> results;
  for (Backend b : c.backends) {
    std::unique_ptr<Device> device;
    try {
      device = Device::create({.backend = b});
    } catch (const Error& e) {
      Result r;
      r.method = "*";
      r.backend = b;
      r.error = e.what();
      results.push_back(r);
      continue;
    }
    std::vector<std::string> methods = c.methods;
    if (methods.empty())
      for (const auto& m : listMethods())
        if (b == Backend::Cpu ? m.cpu : m.vulkan) methods.push_back(m.name);
    for (const auto& m : methods) results.push_back(runOne(c, pool, *device, m));
  }
  return results;
}

}  // namespace rtd::soak
