// The emitter-halo measure of issue 12 item 3, shared by the renderer's test
// (tests/render/emitter_halo_test.cpp) and the Blender fixture's (tests/passes/emitter_halo_blender_test.cpp):
// the mean |error| of display luma (Reinhard, sRGB) of the ceiling pixels 1 to 3 pixels from the
// lamp (Chebyshev distance to the nearest pixel with emission) against that of the ceiling 6 or
// more pixels away. The lamp's own pixels are not scored (their emission is added back exactly).
#pragma once
#include <cmath>
#include <cstdio>
#include <string>

#include "passes/tonemap.h"
#include "rtd/rtd.h"

namespace rtd::test {

struct CeilingHalo {
  double near = 0, far = 0, nearBias = 0, farBias = 0;  // mean |error| and mean error
  int nNear = 0, nFar = 0, lampPixels = 0;
  double ratio() const { return near / far; }
  void print(const std::string& name) const {
    std::printf("%s: ceiling next to the lamp |err| %.4f (bias %+.4f, %d px), elsewhere %.4f (bias %+.4f, %d px), ratio %.2f\n",
                name.c_str(), near, nearBias, nNear, far, farBias, nFar, ratio());
  }
};

inline double displayLuma(const Image& img, int x, int y) {
  auto d = [&](int c) { return tonemap::toneMapToSrgb(img.at(x, y, c), tonemap::Operator::Reinhard, 1.0f); };
  return tonemap::luminance(d(0), d(1), d(2));
}

/// `last`: the frame `out` was denoised from (its Emission marks the lamp); `ceiling(x, y)`:
/// whether a pixel is ceiling (the caller knows the scene's axes); lamp pixels never count.
template <class IsCeiling>
CeilingHalo ceilingHalo(const Frame& last, const Image& out, const Image& reference, IsCeiling&& ceiling) {
  const int w = last.width, h = last.height;
  auto emitter = [&](int x, int y) { return last[Buffer::Emission].at(x, y, 0) > 0.0f; };
  auto distance = [&](int x, int y) {  // to the nearest emitter pixel, capped at 9
    for (int r = 1; r <= 8; ++r)
      for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
          const int qx = x + dx, qy = y + dy;
          if (qx >= 0 && qy >= 0 && qx < w && qy < h && emitter(qx, qy)) return r;
        }
    return 9;
  };
  CeilingHalo r;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (emitter(x, y)) {
        ++r.lampPixels;
        continue;
      }
      if (!ceiling(x, y)) continue;
      const int dist = distance(x, y);
      const double e = displayLuma(out, x, y) - displayLuma(reference, x, y);
      if (dist <= 3) r.near += std::abs(e), r.nearBias += e, ++r.nNear;
      if (dist >= 6) r.far += std::abs(e), r.farBias += e, ++r.nFar;
    }
  if (r.nNear) r.near /= r.nNear, r.nearBias /= r.nNear;
  if (r.nFar) r.far /= r.nFar, r.farBias /= r.nFar;
  return r;
}

}  // namespace rtd::test
