// Method "svgf" on two views (rtd/stereo.h), CPU. With components = composite and
// eyeReprojection (the gersthofer variant) both eyes run Gersthofer's pipeline
// (gersthofer.h) in step, and between temporal accumulation and the composite each eye's
// indirect diffuse light is blended with the other eye's, reprojected at its world positions
// (Sec. 3.4.2). With any other settings the eyes are two independent single-view denoisers.
#include <chrono>

#include "backend/cpu/cpu_denoiser.h"
#include "core/stereo_pair.h"
#include "core/timer.h"
#include "methods/svgf/gersthofer.h"
#include "methods/svgf/svgf_passes.h"

namespace rtd {

std::unique_ptr<Denoiser> createSvgfCpu(tbb::task_arena& arena);

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

class SvgfStereoCpu final : public StereoPair {
 public:
  explicit SvgfStereoCpu(tbb::task_arena& arena)
      : StereoPair(createSvgfCpu(arena), createSvgfCpu(arena)), arena_(arena) {}

  void denoise(const StereoFrameInputs& in, const ImageView& left, const ImageView& right) override {
    const SvgfSettings s = getSettings<SvgfSettings>();
    if (s.components != SvgfComponents::composite || !s.eyeReprojection) {
      shared_ = false;  // the two histories below are the single-view denoisers'
      StereoPair::denoise(in, left, right);
      return;
    }
    validate(in, left, right);
    if (!shared_) resetShared();
    shared_ = true;
    const auto start = Clock::now();
    const std::vector<Buffer> used = importedBuffers(requiredBuffers(), svgf::extraBuffers(s), s.reprojection,
                                                     in.eye[0].has(Buffer::Motion) && in.eye[1].has(Buffer::Motion));
    FrameStats stats[2];
    double eyeMs[2] = {0, 0};
    FrameStats pair;
    const ImageView* outs[2] = {&left, &right};
    arena_.execute([&] {
      for (int e = 0; e < 2; ++e) {
        const auto t0 = Clock::now();
        Eye& eye = eyes_[e];
        {
          PassTimer t(stats[e], "import");
          stats[e].sanitizedValues = importFrame(in.eye[e], requiredBuffers(), eye.current, &used, &stats[e].sanitized);
        }
        if (eye.current.width != width_ || eye.current.height != height_ || in.eye[0].cameraCut || in.eye[1].cameraCut) {
          if (e == 0) resetShared();  // a new size or a cut restarts both eyes
          width_ = eye.current.width;
          height_ = eye.current.height;
        }
        eye.pipeline.front(eye.current, eye.hasPrevious ? &eye.previous : nullptr, s, stats[e]);
        eyeMs[e] += msSince(t0);
      }
      if (canShare(eyes_[0].current) && canShare(eyes_[1].current)) {
        PassTimer t(pair, "eyeReprojection");
        svgf::exchangeIndirectDiffuse(eyes_[0].pipeline, eyes_[0].current, eyes_[1].pipeline, eyes_[1].current, s);
      }
      for (int e = 0; e < 2; ++e) {
        const auto t0 = Clock::now();
        Eye& eye = eyes_[e];
        bool emissionIncluded = false;
        const Plane3& result = eye.pipeline.back(eye.current, s, stats[e], emissionIncluded);
        {
          PassTimer t(stats[e], "export");
          const bool addEmission = eye.current.has(Buffer::Emission) && !emissionIncluded;
          exportRgb(result, addEmission ? &eye.current.planes(Buffer::Emission) : nullptr, *outs[e]);
        }
        stats[e].memory = eye.pipeline.memory();
        std::swap(eye.current, eye.previous);
        eye.hasPrevious = true;
        stats[e].memory.push_back({"frames", eye.current.bytes() + eye.previous.bytes()});
        eyeMs[e] += msSince(t0);
      }
    });
    for (int e = 0; e < 2; ++e) {
      stats[e].pixels = uint64_t(width_) * height_;
      stats[e].totalMilliseconds = eyeMs[e];
      eyeStats_[e] = std::move(stats[e]);
    }
    stats_ = combineEyeStats(eyeStats_[0], eyeStats_[1]);
    for (auto& p : pair.passes) stats_.passes.push_back(p);
    stats_.totalMilliseconds = msSince(start);
  }

  void reset() override {
    StereoPair::reset();
    resetShared();
  }

 private:
  // Eye reprojection needs world positions, guides and both cameras.
  static bool canShare(const FrameData& f) {
    return f.has(Buffer::Position) && f.has(Buffer::Normal) && f.has(Buffer::Depth) && f.camera.valid;
  }
  void resetShared() {
    for (auto& e : eyes_) {
      e.hasPrevious = false;
      e.pipeline.reset();
    }
  }

  struct Eye {
    FrameData current, previous;
    bool hasPrevious = false;
    svgf::GersthoferEye pipeline;
  };
  tbb::task_arena& arena_;
  Eye eyes_[2];
  bool shared_ = false;  // the last frame ran the shared pipeline (its histories are current)
  int width_ = 0, height_ = 0;
};


}  // namespace

std::unique_ptr<StereoDenoiser> createSvgfStereoCpu(tbb::task_arena& arena) {
  return std::make_unique<SvgfStereoCpu>(arena);
}

}  // namespace rtd
