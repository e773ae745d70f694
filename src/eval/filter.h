// Separable convolution with clamp-to-edge borders, shared by SSIM and FLIP.
#pragma once
#include <tbb/parallel_for.h>

#include <algorithm>
#include <vector>

namespace rtd::eval::detail {

/// dst = src convolved with kx along x, then ky along y (both odd length, centred), borders
/// clamped to the edge. `tmp` is scratch of the same size. Parallel over rows.
template <class T>
void convolveSeparable(const std::vector<T>& src, std::vector<T>& dst, std::vector<T>& tmp, int w, int h,
                       const std::vector<T>& kx, const std::vector<T>& ky) {
  const int rx = int(kx.size()) / 2, ry = int(ky.size()) / 2;
  tmp.resize(src.size());
  dst.resize(src.size());
  tbb::parallel_for(0, h, [&](int y) {
    const T* s = src.data() + size_t(y) * w;
    T* t = tmp.data() + size_t(y) * w;
    for (int x = 0; x < w; ++x) {
      T sum = 0;
      if (x >= rx && x + rx < w) {
        for (int k = -rx; k <= rx; ++k) sum += kx[k + rx] * s[x + k];
      } else {
        for (int k = -rx; k <= rx; ++k) sum += kx[k + rx] * s[std::clamp(x + k, 0, w - 1)];
      }
      t[x] = sum;
    }
  });
  tbb::parallel_for(0, h, [&](int y) {
    T* d = dst.data() + size_t(y) * w;
    for (int x = 0; x < w; ++x) d[x] = 0;
    for (int k = -ry; k <= ry; ++k) {
      const T* t = tmp.data() + size_t(std::clamp(y + k, 0, h - 1)) * w;
      const T wk = ky[k + ry];
      for (int x = 0; x < w; ++x) d[x] += wk * t[x];
    }
  });
}

}  // namespace rtd::eval::detail
