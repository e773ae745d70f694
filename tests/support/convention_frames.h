// The synthetic scene given in an engine's conventions (rtd::FrameConventions), converted here
// in double precision independently of src/core/conventions.cpp, and a runner that denoises a
// sequence so that tests can compare the outputs of the same scene in different conventions.
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "rtd/rtd.h"
#include "synthetic/synthetic.h"

namespace rtd::test {

/// Turns frame `index` (native conventions) into an engine's: edits the buffers and sets the
/// conventions that describe them.
using ToEngine = std::function<void(int index, Frame& frame, FrameConventions& conventions)>;

/// Output of each frame of `count` frames of `scene` denoised by `method` (with `settings` by
/// name) on `device`, the frames given through `toEngine` (null: native).
inline std::vector<Image> denoiseSequence(Device& device, const std::string& method,
                                          const std::vector<std::pair<std::string, std::string>>& settings,
                                          const synthetic::Scene& scene, int count, const ToEngine& toEngine) {
  auto denoiser = device.createDenoiser(method);
  for (const auto& [k, v] : settings) denoiser->set(k, v);
  std::vector<Image> out;
  for (int i = 0; i < count; ++i) {
    Frame f = synthetic::makeFrame(scene, i);
    FrameConventions c;
    if (toEngine) toEngine(i, f, c);
    FrameInputs in = f.inputs();
    in.conventions = c;
    out.emplace_back(scene.width, scene.height, 3);
    denoiser->denoise(in, out.back().view());
  }
  return out;
}

/// Largest |a - b| over every frame, pixel and channel.
inline double maxDifference(const std::vector<Image>& a, const std::vector<Image>& b) {
  double m = 0;
  for (size_t i = 0; i < a.size(); ++i)
    for (size_t k = 0; k < a[i].pixels.size(); ++k)
      m = std::max(m, std::abs(double(a[i].pixels[k]) - double(b[i].pixels[k])));
  return m;
}

/// Denoises `frames` frames of `s` with SVGF (it reads motion, normals and depth) natively and
/// through `engine`: the outputs must agree within `tolerance` of the largest output value,
/// while the same engine frames with the conventions left native (ignored) must not (> 2%), so
/// the comparison can tell. A tight normal test makes normals given in the wrong space lose history;
/// the absolute depth eps of the a-trous weight makes depth in the wrong units show (svgf's
/// default, relative to depth, filters reciprocal depth almost as it filters view depth).
inline void expectSameOutput(Device& device, const synthetic::Scene& s, const ToEngine& engine, double tolerance,
                             int frames = 5) {
  const std::vector<std::pair<std::string, std::string>> settings = {
      {"normalTolerance", "0.9999"}, {"depthEpsilon", "0.01"}, {"depthEpsilonRelative", "0"}};
  const auto native = denoiseSequence(device, "svgf", settings, s, frames, nullptr);
  const auto converted = denoiseSequence(device, "svgf", settings, s, frames, engine);
  const auto ignored = denoiseSequence(device, "svgf", settings, s, frames, [&](int i, Frame& f, FrameConventions& c) {
    engine(i, f, c);
    c = FrameConventions{};
  });
  double peak = 0;
  for (const auto& img : native)
    for (float v : img.pixels) peak = std::max(peak, double(v));
  EXPECT_LE(maxDifference(converted, native), tolerance * peak);
  EXPECT_GT(maxDifference(ignored, native), 0.02 * peak);
}

/// Motion in another unit and direction: units (1, 1) pixels, (w, h) UV, (w/2, h/2) NDC.
inline ToEngine motionAs(FrameConventions::MotionUnits units, bool yUp, bool toCurrent) {
  return [=](int, Frame& f, FrameConventions& c) {
    c.motionUnits = units;
    c.motionYUp = yUp;
    c.motionToCurrent = toCurrent;
    double ux = 1, uy = 1;
    if (units == FrameConventions::MotionUnits::Uv) ux = f.width, uy = f.height;
    if (units == FrameConventions::MotionUnits::Ndc) ux = 0.5 * f.width, uy = 0.5 * f.height;
    Image& m = f[Buffer::Motion];
    for (size_t i = 0; i < m.pixels.size(); i += 2) {
      double x = m.pixels[i] / ux, y = m.pixels[i + 1] / uy;
      if (yUp) y = -y;
      if (toCurrent) x = -x, y = -y;
      m.pixels[i] = float(x);
      m.pixels[i + 1] = float(y);
    }
  };
}

/// Motion computed with the jittered projections: true motion - previous jitter + jitter.
inline ToEngine jitteredMotion(const synthetic::Scene& scene) {
  return [=](int i, Frame& f, FrameConventions& c) {
    const auto j = synthetic::jitterOf(scene, i), jp = synthetic::jitterOf(scene, i - 1);
    c.motionIncludesJitter = true;
    c.jitterX = j[0], c.jitterY = j[1], c.previousJitterX = jp[0], c.previousJitterY = jp[1];
    Image& m = f[Buffer::Motion];
    for (size_t k = 0; k < m.pixels.size(); k += 2) {
      m.pixels[k] = float(double(m.pixels[k]) - jp[0] + j[0]);
      m.pixels[k + 1] = float(double(m.pixels[k + 1]) - jp[1] + j[1]);
    }
  };
}

/// No motion vectors: history from the world positions and the (unjittered) cameras, and the jitter.
inline ToEngine jitteredCameraOnly(const synthetic::Scene& scene) {
  return [=](int i, Frame& f, FrameConventions& c) {
    const auto j = synthetic::jitterOf(scene, i);
    c.jitterX = j[0], c.jitterY = j[1];
    f[Buffer::Motion] = Image();
  };
}

/// Normals in the camera space of camera.worldToCamera: n_view = A n_world (A its 3x3).
inline ToEngine viewSpaceNormals() {
  return [](int, Frame& f, FrameConventions& c) {
    c.normalSpace = FrameConventions::NormalSpace::View;
    const auto& a = f.camera.worldToCamera;
    Image& n = f[Buffer::Normal];
    for (size_t k = 0; k < n.pixels.size(); k += 3) {
      const double x = n.pixels[k], y = n.pixels[k + 1], z = n.pixels[k + 2];
      for (int r = 0; r < 3; ++r) n.pixels[k + r] = float(a[r * 4] * x + a[r * 4 + 1] * y + a[r * 4 + 2] * z);
    }
  };
}

/// The depth buffer an engine's projection `p` writes: d = clip.z / clip.w of the camera-space
/// point at z = -depth (x and y do not enter for these projections), remapped from [-1, 1] to
/// [0, 1] for an OpenGL projection.
inline ToEngine hardwareDepth(const std::array<double, 16>& p, FrameConventions::DepthRange range) {
  return [=](int, Frame& f, FrameConventions& c) {
    c.depth = FrameConventions::DepthKind::Hardware;
    c.depthRange = range;
    for (int k = 0; k < 16; ++k) c.depthProjection[k] = float(p[k]);
    for (float& v : f[Buffer::Depth].pixels) {
      const double z = -double(v);
      double ndc = (p[10] * z + p[11]) / (p[14] * z + p[15]);
      if (range == FrameConventions::DepthRange::MinusOneToOne) ndc = 0.5 * ndc + 0.5;
      v = float(ndc);
    }
  };
}

/// Perspective projections (right-handed camera space looking down -z), only the z and w rows
/// matter: Vulkan/D3D [0, 1], OpenGL [-1, 1], and Vulkan reversed-Z with an infinite far plane.
inline std::array<double, 16> zeroToOneProjection(double n, double f) {
  return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, f / (n - f), n * f / (n - f), 0, 0, -1, 0};
}
inline std::array<double, 16> openGlProjection(double n, double f) {
  return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, -(f + n) / (f - n), -2 * f * n / (f - n), 0, 0, -1, 0};
}
inline std::array<double, 16> reversedInfiniteProjection(double n) {
  return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, n, 0, 0, -1, 0};
}

}  // namespace rtd::test
