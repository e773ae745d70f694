// Base of every CPU denoiser: settings by name, frame import with sanitization, history resize
// and reset, per-pass timing, previous-frame features. A method implements process().
#pragma once
#include <algorithm>
#include <chrono>
#include <string>

#include <tbb/task_arena.h>

#include "core/api_guard.h"
#include "core/conventions.h"
#include "core/frame_data.h"
#include "core/settings_reflect.h"
#include "core/validate.h"
#include "core/timer.h"
#include "rtd/denoiser.h"

namespace rtd {

/// Every float array a CPU denoiser keeps, within a frame or across frames, for tests of
/// invariants on intermediate results (no subnormal anywhere, core/flush.h). Reached from a
/// Denoiser by dynamic_cast; not part of the public API.
class PlaneInspection {
 public:
  virtual ~PlaneInspection() = default;
  virtual void forEachPlane(const PlaneVisitor& visit) const = 0;
};

template <class S> class CpuDenoiser : public TypedSettings<S, Denoiser>, public PlaneInspection {
 public:
  explicit CpuDenoiser(tbb::task_arena& arena) : arena_(arena) {}

  Backend backend() const override { return Backend::Cpu; }
  const FrameStats& stats() const override { return stats_; }

  /// Buffers the method reads beyond its required ones and the shared passes' (importedBuffers()).
  virtual std::vector<Buffer> extraBuffers() const { return {}; }

  void reset() override {
    hasPrevious_ = false;
    resetHistory();
  }

  /// The imported frames, the output planes and what the method adds (visitMethodPlanes).
  void forEachPlane(const PlaneVisitor& visit) const final {
    for (const FrameData* f : {&current_, &previous_})
      for (const auto& planes : f->buffers)
        for (const Plane& p : planes) visitPlane(visit, "frame", p);
    visitPlanes(visit, "output", output_);
    visitMethodPlanes(visit);
  }

  void denoise(const FrameInputs& frame, const ImageView& output) final {
    guarded("denoise", [&] { denoiseFrame(frame, output); });
  }

 private:
  void denoiseFrame(const FrameInputs& frame, const ImageView& output) {
    FrameStats stats;
    auto start = std::chrono::steady_clock::now();
    // Recomputed per frame: the lists may depend on the settings.
    used_ = importedBuffers(this->requiredBuffers(), extraBuffers(), this->settings_.reprojection, frame.has(Buffer::Motion));
    // Everything is checked before history is touched (the Vulkan backend checks the same).
    checkInputViews(frame, this->requiredBuffers());
    checkOutputView(output, frame[Buffer::Color].width, frame[Buffer::Color].height);
    const ConventionTransform conventions =
        conventionTransform(frame.conventions, frame.camera, frame[Buffer::Color].width,
                            frame[Buffer::Color].height, frame.has(Buffer::Normal));
    arena_.execute([&] {
      {
        PassTimer t(stats, "import");
        stats.sanitizedValues = importFrame(frame, this->requiredBuffers(), current_, &used_, &stats.sanitized);
      }
      if (conventions.convertsPlanes()) {
        PassTimer t(stats, "conventions");
        applyConventions(conventions, current_);
      }
      const int w = current_.width, h = current_.height;
      if (w != width_ || h != height_) {
        width_ = w;
        height_ = h;
        resizeHistory(w, h);
        for (auto& c : output_) c.resize(w, h);
        reset();
      } else if (frame.cameraCut) {
        reset();
      }
      if (hasPrevious_) previous_.camera = jitterCompensated(previous_.camera, conventions, w, h);
      const std::vector<Plane>* emission = current_.has(Buffer::Emission) ? &current_.planes(Buffer::Emission) : nullptr;
      const RgbExport outputRows(output, w, h, emission);
      outputRows_ = &outputRows;
      exported_ = false;
      const Plane3& result = process(current_, hasPrevious_ ? &previous_ : nullptr, output_, stats);
      outputRows_ = nullptr;
      if (!exported_) {
        PassTimer t(stats, "export");
        exportRgb(result, resultHasEmission_ ? nullptr : emission, output);
      }
      std::swap(current_, previous_);
      hasPrevious_ = true;
    });
    if (stats.memory.empty()) stats.memory = memoryUse();
    stats.pixels = uint64_t(width_) * height_;
    stats.totalMilliseconds = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    stats_ = std::move(stats);
  }

  /// FrameStats::memory for the methods that do not account for it themselves: the imported
  /// frames, and every other float plane kept (PlaneInspection; integer arrays such as the
  /// reprojection's taps are not counted).
  std::vector<MemoryUse> memoryUse() const {
    uint64_t all = 0;
    forEachPlane([&](std::string_view, const float*, size_t n) { all += uint64_t(n) * sizeof(float); });
    const uint64_t frames = current_.bytes() + previous_.bytes();
    return {{"frames", frames}, {"planes", all - frames}};
  }

 protected:
  /// Denoise `frame`; returns the planes to export: `out` (planes of the frame's size the method
  /// may fill) or planes of its own (TAA's history, say), so the result is not copied. `previous`
  /// is the last frame's data, or null right after a reset. Time passes with
  /// PassTimer(stats, "name").
  virtual const Plane3& process(const FrameData& frame, const FrameData* previous, Plane3& out,
                                FrameStats& stats) = 0;
  /// (Re)allocate history for a new size; called before the first frame and on resize.
  virtual void resizeHistory(int width, int height) = 0;
  /// Forget history (allocations stay).
  virtual void resetHistory() = 0;
  /// Every plane the method keeps (PlaneInspection).
  virtual void visitMethodPlanes(const PlaneVisitor& visit) const = 0;
  /// For process()'s last pass: the frame's output view with the separated emission added
  /// (RgbExport), to be written row by row while the rows are in cache. Taking it promises
  /// that every row is written (the planes process() returns are then not exported) and that
  /// the result does not hold the emission (resultHasEmission_ stays false).
  const RgbExport* takeOutputRows() {
    exported_ = true;
    return outputRows_;
  }


  tbb::task_arena& arena_;
  FrameData current_, previous_;
  bool hasPrevious_ = false;
  std::vector<Buffer> used_;
  int width_ = 0, height_ = 0;
  Plane3 output_;
  FrameStats stats_;
  /// Set by a process() whose result already holds the separated emission (post-processing
  /// such as a tone map must see it), so that the export does not add it again.
  bool resultHasEmission_ = false;

 private:
  const RgbExport* outputRows_ = nullptr;  // during process()
  bool exported_ = false;                  // process() took outputRows_
};

}  // namespace rtd
