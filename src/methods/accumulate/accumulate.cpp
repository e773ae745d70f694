// Method "accumulate": demodulate, reproject, accumulate, remodulate. The baseline that every
// other method starts from, exposed on its own.
#include "backend/cpu/cpu_denoiser.h"
#include "core/parallel.h"
#include "passes/demodulation.h"
#include "passes/reprojection.h"
#include "passes/temporal_accumulation.h"
#include "rtd/methods/accumulate.h"

namespace rtd {

namespace {
class AccumulateCpu final : public CpuDenoiser<AccumulateSettings> {
 public:
  using CpuDenoiser::CpuDenoiser;
  std::vector<Buffer> requiredBuffers() const override { return {Buffer::Color}; }

 protected:
  void resizeHistory(int w, int h) override { accumulator_.resize(w, h); }
  void resetHistory() override { accumulator_.reset(); }
  void visitMethodPlanes(const PlaneVisitor& visit) const override {
    reprojection_.forEachPlane(visit);
    accumulator_.forEachPlane(visit);
  }

  const Plane3& process(const FrameData& frame, const FrameData* previous, Plane3& out, FrameStats& stats) override {
    const auto* albedo = settings_.demodulate && frame.has(Buffer::Albedo) ? &frame.planes(Buffer::Albedo) : nullptr;
    {
      PassTimer t(stats, "reproject");
      reproject(frame, previous, settings_.reprojection, reprojection_);
    }
    {
      PassTimer t(stats, "accumulate");  // of the radiance, demodulated on the fly
      AccumulationOptions opt;
      opt.albedo = albedo;
      accumulator_.run(reprojection_, frame.planes(Buffer::Color), settings_.alpha, settings_.alpha,
                       settings_.maxHistoryLength, opt);
    }
    PassTimer t(stats, "remodulate");
    parallelRows(frame.height, [&](int y) { remodulateRow(accumulator_.color(), albedo, out, y); });
    return out;
  }

 private:
  Reprojection reprojection_;
  TemporalAccumulator accumulator_;
};
}  // namespace

std::unique_ptr<Denoiser> createAccumulateCpu(tbb::task_arena& arena) { return std::make_unique<AccumulateCpu>(arena); }

}  // namespace rtd
