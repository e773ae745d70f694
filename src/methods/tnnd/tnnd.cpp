// Method "tnnd" on the CPU: [accumulate] -> encode -> `iterations` automaton steps -> decode
// (tnnd_model.h). The weights are read when the denoiser is created and whenever the setting
// "weights" changes (a bad file is reported by set() and the old weights stay).
#include "backend/cpu/cpu_denoiser.h"
#include "methods/tnnd/tnnd_model.h"
#include "passes/reprojection.h"
#include "passes/temporal_accumulation.h"
#include "rtd/methods/tnnd.h"

namespace rtd {

namespace {

class TnndCpu final : public CpuDenoiser<TnndSettings> {
 public:
  explicit TnndCpu(tbb::task_arena& arena) : CpuDenoiser(arena), weights_(tnnd::loadWeights("")) {}
  std::vector<Buffer> requiredBuffers() const override { return {Buffer::Color, Buffer::Normal, Buffer::Albedo}; }

 protected:
  void settingsChanged() override {
    if (settings_.weights == loaded_) return;
    try {
      weights_ = tnnd::loadWeights(settings_.weights);
      loaded_ = settings_.weights;
    } catch (...) {
      settings_.weights = loaded_;  // the setting keeps naming the weights in use
      throw;
    }
  }
  void resizeHistory(int w, int h) override {
    accumulator_.resize(w, h);
    for (auto& s : state_) tnnd::resize(s, w, h);
  }
  void resetHistory() override { accumulator_.reset(); }
  void visitMethodPlanes(const PlaneVisitor& visit) const override {
    for (const auto& st : state_)
      for (const Plane& p : st) visitPlane(visit, "automaton state", p);
    reprojection_.forEachPlane(visit);
    accumulator_.forEachPlane(visit);
  }

  const Plane3& process(const FrameData& frame, const FrameData* previous, Plane3& out, FrameStats& stats) override {
    const Plane* color = frame.planes(Buffer::Color).data();
    if (settings_.accumulate) {
      {
        PassTimer t(stats, "reproject");
        reproject(frame, previous, settings_.reprojection, reprojection_);
      }
      PassTimer t(stats, "accumulate");
      AccumulationOptions opt;
      opt.moments = false;
      accumulator_.run(reprojection_, frame.planes(Buffer::Color), settings_.alpha, settings_.alpha,
                       settings_.maxHistoryLength, opt);
      color = accumulator_.color().data();
    }
    {
      PassTimer t(stats, "encode");
      tnnd::encode(color, frame.planes(Buffer::Normal), frame.planes(Buffer::Albedo), frame.camera, state_[0]);
    }
    int cur = 0;
    for (int i = 0; i < settings_.iterations; ++i) {
      PassTimer t(stats, "step" + std::to_string(i + 1));
      tnnd::step(weights_, state_[cur], state_[cur ^ 1]);
      cur ^= 1;
    }
    PassTimer t(stats, "decode");
    tnnd::decode(state_[cur], out);
    return out;
  }

 private:
  tnnd::Weights weights_;
  std::string loaded_;  // the "weights" setting weights_ came from ("" = built-in)
  tnnd::State state_[2];
  Reprojection reprojection_;
  TemporalAccumulator accumulator_;
};

}  // namespace

std::unique_ptr<Denoiser> createTnndCpu(tbb::task_arena& arena) { return std::make_unique<TnndCpu>(arena); }

}  // namespace rtd
