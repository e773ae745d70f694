// Synthetic guide frames and non-guide samples for the guide-ray tests (CPU:
// tests/passes/guide_rays_test.cpp; Vulkan: tests/vulkan/guide_rays_vulkan_test.cpp).
#pragma once
#include <utility>

#include "rtd/guide_rays.h"

namespace rtd::test {

// A guide frame: constant normal +z, the given colour, depth from `depth(x, y)` (centres).
template <class Depth> Frame guideFrame(int w, int h, Depth depth, float color) {
  Frame f;
  f.width = w;
  f.height = h;
  f[Buffer::Color] = Image(w, h, 3, color);
  f[Buffer::Depth] = Image(w, h, 1);
  f[Buffer::Normal] = Image(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      f[Buffer::Depth].at(x, y) = depth(float(x), float(y));
      f[Buffer::Normal].at(x, y, 2) = 1.0f;
    }
  return f;
}

// `n` non-guide samples at the offsets `offset(k, x, y)`; depth and colour from their positions.
template <class Offset, class Depth, class Color>
GuideRaySamples samplesAt(int w, int h, int n, Offset offset, Depth depth, Color color) {
  GuideRaySamples s;
  for (int k = 1; k <= n; ++k) {
    Frame f = guideFrame(w, h, [](float, float) { return 1.0f; }, 0.0f);
    Image off(w, h, 2);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const auto [ox, oy] = offset(k, x, y);
        off.at(x, y, 0) = ox;
        off.at(x, y, 1) = oy;
        f[Buffer::Depth].at(x, y) = depth(x + ox, y + oy);
        for (int c = 0; c < 3; ++c) f[Buffer::Color].at(x, y, c) = color(x + ox, y + oy);
      }
    s.samples.push_back(std::move(f));
    s.offsets.push_back(std::move(off));
  }
  return s;
}

}  // namespace rtd::test
