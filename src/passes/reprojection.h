// Shared pass: reprojection of the previous frame onto the current one, with per-tap
// consistency tests (Schied et al. 2017 Sec. 4.1; Higginson Sec. 1.3.1, Eq. 1.4).
#pragma once
#include <array>
#include <cstdint>
#include <cstring>
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


/// The 3x3 fallback kernel of Higginson Eq. 1.4 (a Gaussian with sigma ~ 1.04 px), row-major.
extern const float kFallbackKernel3x3[9];

/// Fills `out` for the current frame. With `previous == nullptr` every pixel is None.
/// The motion of a pixel is Buffer::Motion if the frame has it; otherwise, if both frames have
/// valid cameras and the current frame has Buffer::Position, the projection of the position
/// with the previous camera (a static scene); otherwise zero.
void reproject(const FrameData& current, const FrameData* previous, const ReprojectionSettings& s,
               Reprojection& out);
/// reproject() for rows [rowBegin, rowEnd) only, on the calling thread, so a method can run
/// the passes that follow on a band of rows while it is in cache. `out` must already have the
/// frame's size. Every row depends only on the current frame's same row and on the previous
/// frame.
void reprojectRows(const FrameData& current, const FrameData* previous, const ReprojectionSettings& s,
                   Reprojection& out, int rowBegin, int rowEnd);

}  // namespace rtd
