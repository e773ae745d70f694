// Shared pass: reprojection of the previous frame onto the current one, with per-tap
// consistency tests (Schied et al. 2017 Sec. 4.1; Higginson Sec. 1.3.1, Eq. 1.4).
#pragma once
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <vector>

#include "core/frame_data.h"
#include "rtd/methods/reprojection.h"

namespace rtd {

/// Where each pixel's history comes from, computed once per frame and used to gather any
/// history plane (colour, moments, history length, BMFR's accumulations).
struct Reprojection {
  enum Kind : uint8_t { None = 0, Bilinear = 1, Fallback3x3 = 2 };
  int width = 0, height = 0;
  PixelVector<uint8_t> kind;                     ///< per pixel
  PixelVector<int32_t> base;                     ///< bilinear: index of the top-left tap (always inside); 3x3: of the centre
  PixelVector<std::array<float, 4>> weights;     ///< bilinear: renormalized weights of the 2x2 taps
  PixelVector<uint16_t> mask3x3;                 ///< 3x3: bit (dy+1)*3+(dx+1) set where the tap is valid
  Plane prevX, prevY;                            ///< reprojected continuous position, pixel units (centre of pixel i at i + 0.5)

  void resize(int w, int h);

  /// Previous position of a pixel that has no history at all: off every frame, so TAA (which
  /// takes the history at any reprojected position inside the frame) keeps the current colour.
  static constexpr float kOffFrame = -1e6f;
  /// Pixel i without history: kind None, position kOffFrame.
  void clearHistory(size_t i) {
    kind[i] = None;
    prevX.data[i] = prevY.data[i] = kOffFrame;
  }

  /// History value of plane `h` (previous frame's size) for pixel index i; 0 for None.
  float gather(const Plane& h, size_t i) const {
    const float* p = h.ptr();
    switch (kind[i]) {
      case Bilinear: return gatherBilinear(p, h.width, i);
      case Fallback3x3: return gather3x3(h, i);
      default: return 0.0f;
    }
  }

  /// The history taps of pixel i as (index, weight) pairs with weights summing to 1, so
  /// several planes can be gathered with one decode. Returns the number of taps (0 for None).
  struct Taps {
    int32_t index[9];
    float weight[9];
    int count = 0;
    float gather(const Plane& h) const {
      float v = 0.0f;
      for (int t = 0; t < count; ++t) v += weight[t] * h.ptr()[index[t]];
      return v;
    }
  };
  int taps(size_t i, Taps& out) const;

  /// Bilinear history of a Bilinear pixel: all four taps lie inside the previous frame
  /// (reproject() slides the footprint inside, taps outside having weight 0).
  float gatherBilinear(const float* h, int width, size_t i) const {
    const int b = base[i];
    const auto& wt = weights[i];
    return wt[0] * h[b] + wt[1] * h[b + 1] + wt[2] * h[b + width] + wt[3] * h[b + width + 1];
  }

  /// The float arrays: bilinear weights and previous positions (PlaneVisitor).
  void forEachPlane(const PlaneVisitor& visit) const {
    visit("reprojection weights", weights.empty() ? nullptr : weights[0].data(), 4 * weights.size());
    visitPlane(visit, "previous x", prevX);
    visitPlane(visit, "previous y", prevY);
  }

  /// Number of pixels of each kind (for tests and statistics).
  std::array<size_t, 3> counts() const;

 private:
  float gather3x3(const Plane& h, size_t i) const;
};


/// Makes pixel i of `out` a Bilinear record for the continuous previous position (px, py)
/// (pixel units, centres at i + 0.5) of a frame of out's size, keeping the taps (tx, ty) for
/// which valid(tx, ty) holds, renormalized; taps outside the frame weigh 0 and the 2x2 window
/// is slid inside so gathers need no bounds checks. Returns false, leaving the record as it
/// was, when no tap is valid (accepted weight <= 1e-4) or the frame is narrower than 2 pixels.
template <class Valid> bool setBilinear(Reprojection& out, size_t i, float px, float py, Valid&& valid) {
  const int w = out.width, h = out.height;
  // Bilinear footprint: taps are pixel centres, so the top-left tap is floor(p - 0.5).
  const float fx = px - 0.5f, fy = py - 0.5f;
  if (!(std::abs(fx) < 1e6f && std::abs(fy) < 1e6f) || w < 2 || h < 2) return false;
  const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
  const float ax = fx - x0, ay = fy - y0;
  const float bw[4] = {(1 - ax) * (1 - ay), ax * (1 - ay), (1 - ax) * ay, ax * ay};
  const int tx[4] = {x0, x0 + 1, x0, x0 + 1}, ty[4] = {y0, y0, y0 + 1, y0 + 1};
  float sum = 0.0f;
  std::array<float, 4> wt{0, 0, 0, 0};
  for (int t = 0; t < 4; ++t)
    if (bw[t] > 0.0f && tx[t] >= 0 && ty[t] >= 0 && tx[t] < w && ty[t] < h && valid(tx[t], ty[t])) {
      wt[t] = bw[t];
      sum += bw[t];
    }
  if (!(sum > 1e-4f)) return false;
  for (auto& v : wt) v /= sum;
  int bx = x0, by = y0;
  if (bx < 0) { bx = 0; wt = {wt[1], 0.0f, wt[3], 0.0f}; }
  if (bx > w - 2) { bx = w - 2; wt = {0.0f, wt[0], 0.0f, wt[2]}; }
  if (by < 0) { by = 0; wt = {wt[2], wt[3], 0.0f, 0.0f}; }
  if (by > h - 2) { by = h - 2; wt = {0.0f, 0.0f, wt[0], wt[1]}; }
  out.kind[i] = Reprojection::Bilinear;
  out.base[i] = by * w + bx;
  out.weights[i] = wt;
  return true;
}

/// A camera's world-to-clip transform of directions (points at infinity, w = 0): the 4x3
/// matrix (projection x worldToCamera)[:, 0:3], row-major.
inline std::array<float, 12> directionToClip(const Camera& c) {
  std::array<float, 12> a{};
  for (int r = 0; r < 4; ++r)
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j) a[size_t(r) * 3 + k] += c.projection[size_t(r) * 4 + j] * c.worldToCamera[size_t(j) * 4 + k];
  return a;
}

/// Previous position (pixels) of the point at infinity seen through current pixel position
/// (sx, sy): the sky of a pixel without geometry, whose world position means nothing. The
/// direction d solves (A_x - ndc_x A_w) . d = (A_y - ndc_y A_w) . d = 0 with A_w . d > 0 (A =
/// directionToClip of the current camera): the cross product of the two rows. False where the
/// camera has no such direction (orthographic) or the previous camera looks away from it.
inline bool reprojectDirection(const std::array<float, 12>& cur, const std::array<float, 12>& prev, float sx, float sy,
                               int w, int h, float& px, float& py) {
  const float nx = 2.0f * sx / float(w) - 1.0f, ny = 1.0f - 2.0f * sy / float(h);
  float r0[3], r1[3];
  for (int k = 0; k < 3; ++k) r0[k] = cur[k] - nx * cur[9 + k], r1[k] = cur[3 + k] - ny * cur[9 + k];
  float d[3] = {r0[1] * r1[2] - r0[2] * r1[1], r0[2] * r1[0] - r0[0] * r1[2], r0[0] * r1[1] - r0[1] * r1[0]};
  const float cw = cur[9] * d[0] + cur[10] * d[1] + cur[11] * d[2];
  if (!(std::abs(cw) > 0.0f)) return false;
  if (cw < 0.0f) for (float& v : d) v = -v;
  float c[4];
  for (int r = 0; r < 4; ++r) c[r] = prev[size_t(r) * 3] * d[0] + prev[size_t(r) * 3 + 1] * d[1] + prev[size_t(r) * 3 + 2] * d[2];
  if (!(c[3] > 0.0f)) return false;
  px = (c[0] / c[3] * 0.5f + 0.5f) * float(w);
  py = (0.5f - c[1] / c[3] * 0.5f) * float(h);
  return true;
}

/// The 3x3 fallback kernel of Higginson Eq. 1.4 (a Gaussian with sigma ~ 1.04 px), row-major.
extern const float kFallbackKernel3x3[9];

/// Fills `out` for the current frame. With `previous == nullptr` every pixel is None.
/// The motion of a pixel is Buffer::Motion if the frame has it; otherwise, if both frames have
/// valid cameras and the current frame has Buffer::Position, the projection of the position
/// with the previous camera (a static scene), or for a pixel without geometry (zero normal)
/// the projection of its view direction (reprojectDirection: a sky at infinity); otherwise zero.
/// `afterRows` (may be empty): called after each chunk of rows [rowBegin, rowEnd) on the thread
/// that reprojected it, for a method's own pass over those rows of the frame while they are in
/// cache (SVGF builds its a-trous guide there), as AccumulationOptions::afterRows.
void reproject(const FrameData& current, const FrameData* previous, const ReprojectionSettings& s,
               Reprojection& out, const std::function<void(int rowBegin, int rowEnd)>& afterRows = {});
/// reproject() for rows [rowBegin, rowEnd) only, on the calling thread, so a method can run
/// the passes that follow on a band of rows while it is in cache. `out` must already have the
/// frame's size. Every row depends only on the current frame's same row and on the previous
/// frame.
void reprojectRows(const FrameData& current, const FrameData* previous, const ReprojectionSettings& s,
                   Reprojection& out, int rowBegin, int rowEnd);

}  // namespace rtd
