#include "passes/fxaa.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/parallel.h"
#include "passes/tonemap.h"

namespace rtd {

float fxaaLuma(float r, float g, float b) {
  const float y = std::max(0.0f, luminance(r, g, b));
  return std::sqrt(y / (1.0f + y));
}

namespace {

// Search steps along the edge, in pixels (the quality preset's schedule).
constexpr float kSteps[12] = {1.0f, 1.0f, 1.0f, 1.0f, 1.0f, 1.5f, 2.0f, 2.0f, 2.0f, 2.0f, 4.0f, 8.0f};

struct FxaaImage {
  const Plane3& rgb;
  const Plane& luma;
  int w, h;
  float l(int x, int y) const { return luma(std::clamp(x, 0, w - 1), std::clamp(y, 0, h - 1)); }
  // Bilinear at continuous pixel coordinates (centres at integers here), clamped to the edge.
  template <class F> float bilinear(F at, float x, float y) const {
    const float fx = std::floor(x), fy = std::floor(y);
    const float ax = x - fx, ay = y - fy;
    const int x0 = int(fx), y0 = int(fy);
    return (1 - ay) * ((1 - ax) * at(x0, y0) + ax * at(x0 + 1, y0)) + ay * ((1 - ax) * at(x0, y0 + 1) + ax * at(x0 + 1, y0 + 1));
  }
  float lumaAt(float x, float y) const {
    return bilinear([&](int i, int j) { return l(i, j); }, x, y);
  }
  float colorAt(int c, float x, float y) const {
    return bilinear([&](int i, int j) { return rgb[c](std::clamp(i, 0, w - 1), std::clamp(j, 0, h - 1)); }, x, y);
  }
};

// The shift of pixel (x, y) in pixels along (sx, sy) (0 where it is not on an edge).
void fxaaPixel(const FxaaImage& im, const FxaaParams& p, int x, int y, float& sx, float& sy) {
  sx = sy = 0.0f;
  const float m = im.l(x, y), n = im.l(x, y - 1), s = im.l(x, y + 1), e = im.l(x + 1, y), wv = im.l(x - 1, y);
  const float hi = std::max({m, n, s, e, wv}), lo = std::min({m, n, s, e, wv});
  const float range = hi - lo;
  if (range < std::max(p.edgeThresholdMin, hi * p.edgeThreshold)) return;
  const float nw = im.l(x - 1, y - 1), ne = im.l(x + 1, y - 1), sw = im.l(x - 1, y + 1), se = im.l(x + 1, y + 1);

  // Sub-pixel aliasing: contrast of the pixel against its 3x3 low-pass, relative to the range.
  const float lowpass = (2.0f * (n + s + e + wv) + (nw + ne + sw + se)) / 12.0f;
  const float t = std::clamp(std::abs(lowpass - m) / range, 0.0f, 1.0f);
  const float smooth = t * t * (3.0f - 2.0f * t);
  const float subpixelShift = smooth * smooth * p.subpixel;

  // Edge orientation from the second differences of the 3x3 neighbourhood: across the rows
  // (a horizontal edge) against across the columns (a vertical one).
  const float acrossRows = std::abs(nw + sw - 2 * wv) + 2 * std::abs(n + s - 2 * m) + std::abs(ne + se - 2 * e);
  const float acrossColumns = std::abs(nw + ne - 2 * n) + 2 * std::abs(wv + e - 2 * m) + std::abs(sw + se - 2 * s);
  const bool horizontalEdge = acrossRows >= acrossColumns;
  // The side across the edge with the steeper gradient.
  const float l1 = horizontalEdge ? n : wv, l2 = horizontalEdge ? s : e;
  const float g1 = std::abs(l1 - m), g2 = std::abs(l2 - m);
  const bool towardsFirst = g1 >= g2;
  const float across = towardsFirst ? -1.0f : 1.0f;  // unit step across the edge (up/left = -1)
  const float edgeMean = 0.5f * (m + (towardsFirst ? l1 : l2));
  const float threshold = 0.25f * std::max(g1, g2);

  // Walk along the edge, half a pixel towards the chosen side, until the luma leaves it.
  const float ox = horizontalEdge ? 0.0f : 0.5f * across, oy = horizontalEdge ? 0.5f * across : 0.0f;
  const float dx = horizontalEdge ? 1.0f : 0.0f, dy = horizontalEdge ? 0.0f : 1.0f;
  float distNeg = 0.0f, distPos = 0.0f, endNeg = 0.0f, endPos = 0.0f;
  bool doneNeg = false, donePos = false;
  for (float step : kSteps) {
    if (!doneNeg) {
      distNeg += step;
      endNeg = im.lumaAt(float(x) + ox - dx * distNeg, float(y) + oy - dy * distNeg) - edgeMean;
      doneNeg = std::abs(endNeg) >= threshold;
    }
    if (!donePos) {
      distPos += step;
      endPos = im.lumaAt(float(x) + ox + dx * distPos, float(y) + oy + dy * distPos) - edgeMean;
      donePos = std::abs(endPos) >= threshold;
    }
    if (doneNeg && donePos) break;
  }
  // At the nearer end the luma must move away from the pixel's side, else the pixel is not the
  // one to shift.
  const bool negCloser = distNeg < distPos;
  const float endLuma = negCloser ? endNeg : endPos;
  const bool correct = (endLuma < 0.0f) != (m - edgeMean < 0.0f);
  const float edgeShift = correct ? 0.5f - std::min(distNeg, distPos) / (distNeg + distPos) : 0.0f;
  const float shift = std::max(edgeShift, subpixelShift);
  if (horizontalEdge) sy = shift * across;
  else sx = shift * across;
}

}  // namespace

void fxaa(const Plane3& in, const FxaaParams& p, Plane& luma, Plane3& out) {
  const int w = in[0].width, h = in[0].height;
  parallelRows(h, [&](int y) {
    for (int x = 0; x < w; ++x) luma(x, y) = fxaaLuma(in[0](x, y), in[1](x, y), in[2](x, y));
  });
  const FxaaImage im{in, luma, w, h};
  parallelRows(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      float sx, sy;
      fxaaPixel(im, p, x, y, sx, sy);
      for (int c = 0; c < 3; ++c)
        out[c](x, y) = sx == 0.0f && sy == 0.0f ? in[c](x, y) : im.colorAt(c, float(x) + sx, float(y) + sy);
    }
  });
}

void toneMapAces(Plane3& rgb) {
  for (auto& plane : rgb)
    parallelRows(plane.height, [&](int y) {
      float* r = plane.row(y);
      for (int x = 0; x < plane.width; ++x) r[x] = tonemap::acesNarkowicz(r[x]);
    });
}

}  // namespace rtd
