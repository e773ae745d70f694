// Inputs of the TAA tests (tests/core/taa_test.cpp, tests/passes/taa_own_surface_test.cpp): a
// reprojection record moving every pixel's history by a constant offset with every tap
// accepted (as reproject() writes it), and colour images from a function of (x, y, channel).
#pragma once
#include "core/plane.h"
#include "passes/reprojection.h"

namespace rtd::test {

/// Every pixel's history comes from (x + dx, y + dy): prev = p + 0.5 + (dx, dy); every 2x2 tap
/// accepted (Catmull-Rom and history rejection read the record).
inline Reprojection shiftedReprojection(int w, int h, float dx, float dy) {
  Reprojection rp;
  rp.resize(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      rp.prevX(x, y) = x + 0.5f + dx;
      rp.prevY(x, y) = y + 0.5f + dy;
      setBilinear(rp, size_t(y) * w + x, rp.prevX(x, y), rp.prevY(x, y), [](int, int) { return true; });
    }
  return rp;
}

template <class F> Plane3 imageOf(int w, int h, F f) {
  Plane3 p;
  resize(p, w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) p[c](x, y) = f(x, y, c);
  return p;
}

}  // namespace rtd::test
