// Shared pass: temporal anti-aliasing with neighbourhood clamping (Karis 2014): the previous
// output, reprojected bilinearly, is clamped to the min/max box of the current 3x3
// neighbourhood in YCoCg and blended with the current frame.
#pragma once
#include <tbb/enumerable_thread_specific.h>

#include <vector>

#include "core/plane.h"
#include "passes/reprojection.h"
#include "rtd/methods/taa.h"

namespace rtd {

class Taa {
 public:
  void resize(int w, int h);
  void reset() { valid_ = false; }
  /// `color` is the current remodulated output; returns the result, which is also the next
  /// frame's history (valid until the next run()). Uses the reprojected positions of `rp` (no
  /// consistency tests: the clamp rejects ghosts).
  const Plane3& run(const Reprojection& rp, const Plane3& color, float alpha);

  /// run() in steps, for methods that run their passes on bands of rows: begin() once per
  /// frame, then runRows() once for every row, from any thread, each call once rows
  /// [rowBegin - 1, rowEnd] of `color` are final (the 3x3 box); the output is then result().
  void begin(int width, int height);
  void runRows(const Reprojection& rp, const Plane3& color, float alpha, int rowBegin, int rowEnd);
  const Plane3& result() const { return history_[cur_]; }
  /// Both histories and this thread's window rows (PlaneVisitor).
  void forEachPlane(const PlaneVisitor& visit) const {
    for (const Plane3& h : history_) visitPlanes(visit, "taa history", h);
    for (const Window& w : windows_) visit("taa window", w.rows.data(), w.rows.size());
  }

 private:
  /// Per-thread rows: the 3x3 box is built from a rolling window of three rows' YCoCg and
  /// their horizontal min/max, so it never goes through memory (the pass is bandwidth-bound).
  struct Window {
    std::vector<float> rows;  // 3 slots x {Y, Co, Cg, min Y, min Co, min Cg, max Y, max Co, max Cg} + 3 history rows
    int slotRow[3] = {-1, -1, -1};
  };
  Plane3 history_[2];
  int cur_ = 0;
  int width_ = 0;
  tbb::enumerable_thread_specific<Window> windows_;
  bool valid_ = false;
  bool first_ = false;  // this frame has no history: the output is the input
};

}  // namespace rtd
