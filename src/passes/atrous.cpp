#include "passes/atrous.h"

#include <cassert>
#include <cstring>

#include "core/parallel.h"
#include "passes/atrous_kernels.h"

namespace rtd {

void PaddedPlane::resize(int w, int h, int padding) {
  constexpr int a = kAlignment;
  pad = (std::max(padding, a) + a - 1) / a * a;
  width = w;
  height = h;
  stride = (w + a - 1) / a * a + 2 * pad;
  if (stride / a % 2 == 0) stride += a;  // an odd count of lines (PaddedPlane)
  // One extra row plus a vector of slack: the last tile of the last row may read past it.
  data.assign(size_t(h + 2 * pad + 1) * stride + a, 0.0f);
}

void PaddedPlane::copyFrom(const Plane& p) {
  parallelRows(height, [&](int y) { std::copy(p.row(y), p.row(y) + width, row(y)); });
}

void PaddedPlane::copyTo(Plane& p) const {
  parallelRows(height, [&](int y) { std::copy(row(y), row(y) + width, p.row(y)); });
}

void AtrousGuide::resize(int w, int h, int pad) {
  for (PaddedPlane* p : {&depth, &normal[0], &normal[1], &normal[2], &gradX, &gradY}) p->resize(w, h, pad);
}

void AtrousGuide::build(const Plane& z, const std::vector<Plane>& n, const std::vector<Plane>* grad, float maxDepthSlope) {
  tbb::parallel_for(tbb::blocked_range<int>(0, depth.height, 4), [&](const tbb::blocked_range<int>& rows) {
    buildRows(z, n, grad, maxDepthSlope, rows.begin(), rows.end());
  });
}

void AtrousGuide::buildRows(const Plane& z, const std::vector<Plane>& n, const std::vector<Plane>* grad,
                            float maxDepthSlope, int rowBegin, int rowEnd) {
  const int w = depth.width, h = depth.height;
  for (int y = rowBegin; y < rowEnd; ++y) {
    std::copy(z.row(y), z.row(y) + w, depth.row(y));
    for (int c = 0; c < 3; ++c) std::copy(n[c].row(y), n[c].row(y) + w, normal[c].row(y));
    float *gx = gradX.row(y), *gy = gradY.row(y);
    const float* zr = z.row(y);
    if (grad) {
      std::copy((*grad)[0].row(y), (*grad)[0].row(y) + w, gx);
      std::copy((*grad)[1].row(y), (*grad)[1].row(y) + w, gy);
    } else {
      // Each axis: the one-sided difference of smaller magnitude (the one that does not cross
      // a depth edge), the only one at the frame's border. The loops over the row's interior
      // have no branch, so they vectorize.
      const float* up = z.row(std::max(y - 1, 0));
      const float* dn = z.row(std::min(y + 1, h - 1));
      auto smaller = [](float a, float b) { return std::abs(a) < std::abs(b) ? a : b; };
      if (w == 1) {
        gx[0] = 0.0f;
      } else {
        gx[0] = zr[1] - zr[0];
        for (int x = 1; x < w - 1; ++x) gx[x] = smaller(zr[x] - zr[x - 1], zr[x + 1] - zr[x]);
        gx[w - 1] = zr[w - 1] - zr[w - 2];
      }
      if (y == 0) {  // (h = 1: dn is this row, the gradient 0)
        for (int x = 0; x < w; ++x) gy[x] = dn[x] - zr[x];
      } else if (y == h - 1) {
        for (int x = 0; x < w; ++x) gy[x] = zr[x] - up[x];
      } else {
        for (int x = 0; x < w; ++x) gy[x] = smaller(zr[x] - up[x], dn[x] - zr[x]);
      }
    }
    if (maxDepthSlope > 0.0f) {
      // |gx ox + gy oy| >= 2^32 |ox + (sqrt 2 - 1) oy| > 5e7 for any non-zero integer offset
      // within 64 pixels (the ratio is irrational, the closest approach is 12 - 29 (sqrt 2 - 1)):
      // w_z = 1 to float precision for any depth difference below ~1e3. Selects, not a branch,
      // so the loop vectorizes.
      constexpr float kHugeX = 0x1p32f, kHugeY = 0x1p32f * 0.41421356f;
      for (int x = 0; x < w; ++x) {
        const bool steep = std::max(std::abs(gx[x]), std::abs(gy[x])) > maxDepthSlope * std::abs(zr[x]);
        gx[x] = steep ? kHugeX : gx[x];
        gy[x] = steep ? kHugeY : gy[x];
      }
    }
  }
}

void AtrousImage::resize(int w, int h, int pad) {
  for (PaddedPlane* p : {&color[0], &color[1], &color[2], &lum, &var}) p->resize(w, h, pad);
}

void atrousLevel(const AtrousGuide& g, const AtrousLevel& lv, const AtrousImage& in, AtrousImage& out) {
  const int r = kernelRadius(lv.kernel);
  const PaddedPlane& z = g.depth;
  std::vector<AtrousTap> taps;  // at most 24: small, and the allocator reuses the block
  taps.reserve(24);
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx) {
      if (!dx && !dy) continue;
      const int ox = dx * lv.step, oy = dy * lv.step;
      taps.push_back({ptrdiff_t(oy) * z.stride + ox, kernelWeight1D(lv.kernel, dx) * kernelWeight1D(lv.kernel, dy),
                      float(dx * dx + dy * dy)});
    }
  // atrousRows' contract (atrous_kernels.h): the list above is point-symmetric (tap k opposite
  // tap n-1-k), and the first half's tap k is at kernel offset (k % (2r + 1) - r, k / (2r + 1) - r).
  for (size_t k = 0; k < taps.size(); ++k) {
    assert(taps[k].offset == -taps[taps.size() - 1 - k].offset);
    assert(2 * k >= taps.size() ||
           taps[k].offset == ptrdiff_t(int(k) / (2 * r + 1) - r) * lv.step * z.stride + (int(k) % (2 * r + 1) - r) * lv.step);
  }
  const float h0 = kernelWeight1D(lv.kernel, 0) * kernelWeight1D(lv.kernel, 0);
  RTD_SIMD(atrousRows)(g, lv, in, out, taps.data(), int(taps.size()), h0);
}

void spatialVariance(const AtrousGuide& g, const PaddedPlane& a, const PaddedPlane& b, const Plane& len,
                     float shortHistory, int radius, float sigmaDepth, float depthEpsilon, float depthEpsilonRelative,
                     int normalExponent, PaddedPlane& var, const PaddedPlane* objectId) {
  RTD_SIMD(spatialVarianceRows)(g, a, b, len, shortHistory, std::min(radius, a.pad), sigmaDepth, depthEpsilon,
                                depthEpsilonRelative, std::max(1, normalExponent), var, objectId);
}

void gaussian3x3(const PaddedPlane& in, PaddedPlane& out) {
  const int w = in.width, h = in.height;
  parallelRows(h, [&](int y) {
    const float* a = in.row(std::max(y - 1, 0));
    const float* b = in.row(y);
    const float* c = in.row(std::min(y + 1, h - 1));
    float* o = out.row(y);
    // Clamp to edge at the image border (the border pixels repeat instead of weighing 0).
    auto at = [&](const float* row, int x) { return row[std::clamp(x, 0, w - 1)]; };
    auto px = [&](int x) {
      return 0.0625f * (at(a, x - 1) + at(a, x + 1) + at(c, x - 1) + at(c, x + 1)) +
             0.125f * (at(a, x) + at(c, x) + at(b, x - 1) + at(b, x + 1)) + 0.25f * b[x];
    };
    if (w < 3) {
      for (int x = 0; x < w; ++x) o[x] = flushTiny(px(x));
      return;
    }
    o[0] = flushTiny(px(0));
    for (int x = 1; x < w - 1; ++x)
      o[x] = flushTiny(0.0625f * (a[x - 1] + a[x + 1] + c[x - 1] + c[x + 1]) +
                       0.125f * (a[x] + c[x] + b[x - 1] + b[x + 1]) + 0.25f * b[x]);
    o[w - 1] = flushTiny(px(w - 1));
  });
}

}  // namespace rtd
