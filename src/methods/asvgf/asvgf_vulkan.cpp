// Method "asvgf" on the Vulkan backend: the passes of asvgf.cpp as compute dispatches. A-SVGF's
// own shaders are in shaders/ here; the gradient's a-trous levels are the shared atrous pass on
// the 1/3-resolution grid, the accumulation the shared pass's temporal_accumulation_gradient
// variant, the variance and colour levels SVGF's GpuFilter.
#if defined(RTD_HAS_VULKAN)
#include "backend/vulkan/vulkan_denoiser.h"
#include "methods/asvgf/asvgf_passes.h"
#include "methods/svgf/svgf_filter_vulkan.h"
#include "rtd/methods/asvgf.h"

namespace rtd {

namespace {

class AsvgfVulkan final : public vk::VulkanDenoiser<AsvgfSettings> {
 public:
  using VulkanDenoiser::VulkanDenoiser;
  std::vector<Buffer> requiredBuffers() const override { return asvgf::requiredBuffers(settings_); }

 protected:
  std::vector<Buffer> extraBuffers() const override { return asvgf::extraBuffers(settings_); }

  void resizeHistory(int w, int h) override {
    reprojection_.allocate(ctx_, w, h, 8);
    depthGradient_.allocate(ctx_, w, h, 2);
    normals_.allocate(ctx_, w, h, 3);
    demod_.allocate(ctx_, w, h, 3);
    accumulator_.resize(ctx_, w, h);
    filter_.resize(ctx_, w, h);
    output_.allocate(ctx_, w, h, 3);
    taa_.resize(w, h);
    const int gw = asvgf::strata(w), gh = asvgf::strata(h);
    gradientDepth_.allocate(ctx_, gw, gh, 1);
    gradientNormal_.allocate(ctx_, gw, gh, 3);
    gradientSlope_.allocate(ctx_, gw, gh, 2);
    for (auto& l : gradientLevels_) l.allocate(ctx_, gw, gh, 5);
    for (auto& v : gradientValid_) v.allocate(ctx_, gw, gh, 1);
    noLuminanceWeight_.allocate(ctx_, gw, gh, 1);
    zeroed_ = false;
  }
  void resetHistory() override {
    accumulator_.reset();
    taa_.reset();
  }

  const vk::Planes& process(vk::Recorder& rec, const vk::GpuFrame& frame, const vk::GpuFrame* previous) override {
    const AsvgfSettings& s = settings_;
    const svgf::FilterParams p = asvgf::filterParams(s);
    const int w = frame.width, h = frame.height, gw = asvgf::strata(w), gh = asvgf::strata(h);
    const vk::Planes* albedo = frame.has(Buffer::Albedo) ? &frame[Buffer::Albedo] : nullptr;
    if (!zeroed_) {
      rec.fill(noLuminanceWeight_.buffer, 0);  // w_l off in the gradient's levels
      zeroed_ = true;
    }
    rec.pass("reproject");
    vk::reproject(rec, frame, previous, s.reprojection, reprojection_);
    rec.pass("features");
    vk::atrousGuide(rec, frame, 0.0f, depthGradient_);
    const bool reflected = s.reflectedNormals && frame.has(Buffer::ReflectedNormal);
    if (reflected) {
      struct PC {
        uint32_t width, height;
      } pc{uint32_t(w), uint32_t(h)};
      rec.dispatch("asvgf_guide_normal", {frame[Buffer::Normal], frame[Buffer::ReflectedNormal], normals_}, pc, w, h);
    }
    const vk::Planes& normal = reflected ? normals_ : frame[Buffer::Normal];
    rec.pass("demodulate");
    vk::demodulate(rec, frame[Buffer::Color], albedo, demod_);

    // The temporal gradient of each stratum, then its a-trous levels.
    const std::vector<vk::Binding> strataOut{frame[Buffer::Depth], normal,         depthGradient_, gradientLevels_[0],
                                             gradientValid_[0],    gradientDepth_, gradientNormal_, gradientSlope_};
    auto bindings = [&](std::vector<vk::Binding> in) {
      in.insert(in.end(), strataOut.begin(), strataOut.end());
      return in;
    };
    const bool samples = s.gradientSource == AsvgfGradientSource::samples;
    if (samples) {
      rec.pass("gradient");
      struct PC {
        uint32_t width, height, gwidth, gheight;
        float scale;
      } pc{uint32_t(w), uint32_t(h), uint32_t(gw), uint32_t(gh), s.antilagScale};
      rec.dispatch("asvgf_gradient",
                   bindings({frame[Buffer::GradientSample], frame[Buffer::GradientPrevious],
                             frame[Buffer::GradientCurrent]}),
                   pc, gw, gh);
    } else {
      // Not A-SVGF: last frame's moments (the accumulator before it runs) against this frame.
      rec.pass("antilag");
      struct PC {
        uint32_t width, height, gwidth, gheight, luminanceMode;
      } pc{uint32_t(w), uint32_t(h), uint32_t(gw), uint32_t(gh), uint32_t(p.variance.luminance)};
      rec.dispatch("asvgf_antilag", bindings({reprojection_, demod_, accumulator_.current()}), pc, gw, gh);
    }
    rec.pass("gradientAtrous");
    int cur = 0;
    for (int i = 0; i < s.gradientIterations; ++i) {
      vk::GpuAtrousLevel lv;
      lv.radius = 1;
      lv.step = 1 << i;
      lv.sigmaDepth = p.variance.sigmaDepth;
      lv.depthEpsilon = p.variance.depthEpsilon;
      lv.depthEpsilonRelative = p.variance.depthEpsilonRelative;
      lv.normalExponent = p.variance.normalExponent;
      lv.sigmaScale = &noLuminanceWeight_;
      lv.prefilterVariance = false;
      lv.propagateVariance = !samples;
      lv.validIn = &gradientValid_[cur];
      lv.validOut = &gradientValid_[cur ^ 1];
      vk::atrousLevel(rec, gradientDepth_, gradientNormal_, gradientSlope_, lv, gradientLevels_[cur],
                      gradientLevels_[cur ^ 1]);
      cur ^= 1;
    }
    if (!samples) {
      struct PC {
        uint32_t gwidth, gheight;
        float noiseSigmas, scale;
      } pc{uint32_t(gw), uint32_t(gh), s.antilagNoiseSigmas, s.antilagScale};
      rec.dispatch("asvgf_antilag_gradient", {gradientLevels_[cur]}, pc, gw, gh);
    }
    rec.pass("accumulate");
    accumulator_.runAdaptive(rec, reprojection_, demod_, s.minAlphaColor, s.minAlphaMoments, s.maxHistoryLength,
                             uint32_t(p.variance.luminance), gradientLevels_[cur], asvgf::kStratum, s.historyExponent);
    const vk::Planes& filtered =
        filter_.run(rec, frame[Buffer::Depth], normal, depthGradient_, accumulator_, demod_, nullptr, p);
    rec.pass("remodulate");
    vk::remodulate(rec, filtered, albedo, output_);
    rec.pass("taa");
    if (!s.taa.taa) return output_;
    // The own-surface box's keys (as asvgf.cpp): object id.
    const bool keyed = s.taa.taaOwnSurface && vk::taaSurfaceKeys(rec, frame, nullptr, nullptr, taaKeys_);
    return taa_.run(rec, reprojection_, output_, s.taa, keyed ? &taaKeys_ : nullptr);
  }

 private:
  vk::Planes reprojection_, depthGradient_, normals_, demod_, output_;
  // The 1/3-resolution gradient: guide (depth, normal, depth gradient), levels, validity.
  vk::Planes gradientDepth_, gradientNormal_, gradientSlope_, gradientLevels_[2], gradientValid_[2];
  vk::Planes noLuminanceWeight_;
  bool zeroed_ = false;
  vk::GpuTemporalAccumulator accumulator_;
  svgf::GpuFilter filter_;
  vk::GpuTaa taa_;
  vk::Planes taaKeys_;  // TaaSettings::taaOwnSurface
};

}  // namespace

std::unique_ptr<Denoiser> createAsvgfVulkan(vk::Context& ctx) { return std::make_unique<AsvgfVulkan>(ctx); }

}  // namespace rtd
#endif
