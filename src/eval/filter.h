// Separable convolution with clamp-to-edge borders, shared by SSIM and FLIP.
#pragma once
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <vector>

namespace rtd::eval::detail {

/// dst = src convolved with kx along x, then ky along y (both odd length, centred), borders
/// clamped to the edge. `tmp` is scratch of the same size. Parallel over rows; both passes
/// loop over taps outside and pixels inside, so the inner loop vectorizes.
template <class T>
void convolveSeparable(const std::vector<T>& src, std::vector<T>& dst, std::vector<T>& tmp, int w, int h,
                       const std::vector<T>& kx, const std::vector<T>& ky) {
  const int rx = int(kx.size()) / 2, ry = int(ky.size()) / 2;
  tmp.resize(src.size());
  dst.resize(src.size());
  tbb::enumerable_thread_specific<std::vector<T>> padded(std::vector<T>(size_t(w + 2 * rx)));
  tbb::parallel_for(0, h, [&](int y) {
    std::vector<T>& pad = padded.local();
    const T* s = src.data() + size_t(y) * w;
    for (int x = -rx; x < w + rx; ++x) pad[x + rx] = s[std::clamp(x, 0, w - 1)];
    T* t = tmp.data() + size_t(y) * w;
    for (int x = 0; x < w; ++x) t[x] = 0;
    for (int k = 0; k <= 2 * rx; ++k) {
      const T wk = kx[k];
      const T* p = pad.data() + k;
      for (int x = 0; x < w; ++x) t[x] += wk * p[x];
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
