// Shared pass: temporal anti-aliasing with neighbourhood clamping (Karis 2014): the previous
// output, reprojected bilinearly or with the 4x4 Catmull-Rom cubic (TaaSettings::
// taaHistoryFilter; Jimenez's SMAA T2x), is clamped to the min/max box of the current 3x3
// neighbourhood in YCoCg (optionally averaged with the 5-tap cross's, as the BMFR code) and
// blended with the current frame, on linear radiance or on display-encoded values
// (TaaSettings::taaDomain; tonemap::taaEncode before, taaDecode after).
#pragma once
#include <tbb/enumerable_thread_specific.h>

#include <vector>

#include "core/frame_data.h"
#include "core/plane.h"
#include "passes/reprojection.h"
#include "rtd/methods/taa.h"

namespace rtd {

/// What the TAA kernel computes (rtd::TaaSettings, decoded once per frame).
struct TaaParams {
  float alpha;        ///< weight of the current frame
  float subpixelAlpha;  ///< its rise with the history fetch's subpixel offset (blendWeights in taa_simd.cpp)
  bool display;       ///< clamp and blend taaEncode()d values; the history holds them too
  float crossWeight;  ///< bounds = box + crossWeight * (cross - box): 0 box3x3, 0.5 boxCross (BMFR)
  bool catmullRom;    ///< history fetch: 4x4 Catmull-Rom instead of bilinear (TaaHistoryFilter)
  bool rejection;     ///< no history where the record's kind is None (TaaSettings::taaHistoryRejection)
  static TaaParams of(const TaaSettings& s) {
    return {s.taaAlpha, s.taaSubpixelAlpha, s.taaDomain == TaaDomain::display, s.taaNeighbourhood == TaaNeighbourhood::boxCross ? 0.5f : 0.0f,
            s.taaHistoryFilter == TaaHistoryFilter::catmullRom, s.taaHistoryRejection};
  }
};

class Taa {
 public:
  /// A new frame size: the history planes are allocated by the first run() (none where TAA
  /// is off).
  void resize(int w, int h);
  void reset() { valid_ = false; }
  /// `color` is the current remodulated output (linear); returns the result, linear, valid
  /// until the next run(). Uses the reprojected positions of `rp` and, with
  /// taaHistoryRejection or the Catmull-Rom filter, its record of accepted taps. `s.taa` is
  /// not looked at (the caller decides whether to run TAA).
  /// `keys`: the pixels' surface keys (taaSurfaceKeys(), passes/taa_keys.h), read with
  /// s.taaOwnSurface: the clamp box of a pixel then takes only its neighbours of its key;
  /// nullptr: the plain box.
  /// `output` (or nullptr): the frame's output view, which then receives each row of the
  /// result as it is blended (RgbExport), and result() is not kept (in the display domain, no
  /// decoded planes are stored).
  const Plane3& run(const Reprojection& rp, const Plane3& color, const TaaSettings& s,
                    const PixelVector<uint32_t>* keys = nullptr, const RgbExport* output = nullptr);

  /// run() in steps, for methods that run their passes on bands of rows: begin() once per
  /// frame, then runRows() once for every row, from any thread, each call once rows
  /// [rowBegin - 1, rowEnd] of `color` are final (the 3x3 box); the output is then result().
  /// `keys` and `output` as in run(); they must stay valid until the last runRows() of the frame.
  void begin(int width, int height, const TaaSettings& s, const PixelVector<uint32_t>* keys = nullptr,
             const RgbExport* output = nullptr);
  void runRows(const Reprojection& rp, const Plane3& color, int rowBegin, int rowEnd);
  /// The linear output: the history itself in the linear domain, its decode in the display one
  /// (not kept in a frame run with an `output` view).
  const Plane3& result() const { return params_.display ? linear_ : history_[cur_]; }
  /// Both histories, the decoded output and this thread's window rows (PlaneVisitor).
  void forEachPlane(const PlaneVisitor& visit) const {
    for (const Plane3& h : history_) visitPlanes(visit, "taa history", h);
    visitPlanes(visit, "taa output", linear_);
    for (const Window& w : windows_) visit("taa window", w.rows.data(), w.rows.size());
  }

 private:
  /// Per-thread rows: the 3x3 box is built from a rolling window of three rows' YCoCg and
  /// their horizontal min/max, so it never goes through memory (the pass is bandwidth-bound).
  struct Window {
    std::vector<float> rows;  // kTaaWindowRows rows (taa_kernels.h): 3 slots, the history, flags, blend weights
    int slotRow[3] = {-1, -1, -1};
  };
  Plane3 history_[2];  // in the frame's domain (display-encoded or linear)
  Plane3 linear_;      // display domain: the decoded output
  int cur_ = 0;
  TaaParams params_{0.1f, 0.0f, false, 0.0f, false, false};
  const uint32_t* keys_ = nullptr;  // this frame's surface keys (taaOwnSurface), or none
  const RgbExport* output_ = nullptr;  // this frame's output view, filled row by row, or none
  bool display_ = false;  // the domain the history holds
  int width_ = 0, height_ = 0;
  tbb::enumerable_thread_specific<Window> windows_;
  bool valid_ = false;
  bool first_ = false;  // this frame has no history: the output is the input
};

}  // namespace rtd
