#include "backend/vulkan/passes.h"

#include <algorithm>

#include "passes/taa.h"

namespace rtd::vk {

Binding GpuFrame::bindingOf(Buffer b, const Context& ctx) const {
  return has(b) ? Binding(planes[int(b)]) : Binding(ctx.dummy());
}

namespace {
struct ModulatePC {
  uint32_t width, height, hasAlbedo;
};
}  // namespace

void demodulate(Recorder& rec, const Planes& color, const Planes* albedo, Planes& out) {
  ModulatePC pc{uint32_t(color.width), uint32_t(color.height), albedo != nullptr};
  rec.dispatch("demodulate", {color, albedo ? Binding(*albedo) : Binding(rec.context().dummy()), out}, pc,
               color.width, color.height);
}

void remodulate(Recorder& rec, const Planes& illumination, const Planes* albedo, Planes& out) {
  ModulatePC pc{uint32_t(out.width), uint32_t(out.height), albedo != nullptr};
  rec.dispatch("remodulate", {illumination, albedo ? Binding(*albedo) : Binding(rec.context().dummy()), out}, pc,
               out.width, out.height);
}

void reproject(Recorder& rec, const GpuFrame& cur, const GpuFrame* prev, const ReprojectionSettings& s, Planes& rp) {
  enum : uint32_t {
    kPrevious = 1, kDepth = 2, kNormal = 4, kId = 8, kPosition = 16, kMotion = 32, kFromCamera = 64,
    kDepthGradient = 128, kFallback = 256, kSky = 512
  };
  struct PC {
    uint32_t width, height, flags;
    float depthTolerance, depthGradientScale, normalTolerance, positionTolerance, positionFootprints;
  } pc{uint32_t(cur.width), uint32_t(cur.height), 0, s.depthTolerance, s.depthGradientScale, s.normalTolerance,
       s.positionTolerance, s.positionFootprints};
  // Same rules as reproject() on the CPU: a test runs when both frames have its buffer.
  const bool usable = prev && prev->width == cur.width && prev->height == cur.height;
  const GpuFrame& p = usable ? *prev : cur;
  if (usable) {
    pc.flags |= kPrevious;
    auto both = [&](Buffer b) { return cur.has(b) && p.has(b); };
    if (s.testDepth && both(Buffer::Depth)) pc.flags |= kDepth;
    if (both(Buffer::Normal)) pc.flags |= kNormal;
    if (s.testObjectId && both(Buffer::ObjectId)) pc.flags |= kId;
    if (s.testsPosition() && both(Buffer::Position)) pc.flags |= kPosition;
    if (cur.has(Buffer::Motion)) pc.flags |= kMotion;
    else if (cur.cameraValue.valid && p.cameraValue.valid && cur.has(Buffer::Position)) {
      pc.flags |= kFromCamera;
      if (cur.has(Buffer::Normal)) pc.flags |= kSky;  // pixels without geometry: their view direction
    }
    if (cur.has(Buffer::DepthGradient)) pc.flags |= kDepthGradient;
    if (s.fallback3x3) pc.flags |= kFallback;
  }
  const Context& ctx = rec.context();
  rec.dispatch("reproject",
               {cur.bindingOf(Buffer::Depth, ctx), p.bindingOf(Buffer::Depth, ctx), cur.bindingOf(Buffer::Normal, ctx),
                p.bindingOf(Buffer::Normal, ctx), cur.bindingOf(Buffer::ObjectId, ctx),
                p.bindingOf(Buffer::ObjectId, ctx), cur.bindingOf(Buffer::Position, ctx),
                p.bindingOf(Buffer::Position, ctx), cur.bindingOf(Buffer::Motion, ctx),
                cur.bindingOf(Buffer::DepthGradient, ctx), p.camera, rp, cur.camera},
               pc, cur.width, cur.height);
}

void GpuTemporalAccumulator::resize(Context& ctx, int w, int h, bool moments) {
  moments_ = moments;
  for (auto& p : history_) p.allocate(ctx, w, h, moments ? 6 : 4);
  cur_ = 0;
}

namespace {
struct AccumulationPC {
  uint32_t width, height;
  float alpha, momentsAlpha, maxHistoryLength;
  uint32_t luminanceMode, cumulativeMoments;
  uint32_t gradientWidth = 0, gradientStride = 1;
  float historyExponent = 0;
  uint32_t options = 0;  // 1: per-pixel alpha (binding 5); 2: clip box (binding 6); 4: fixed weights (Gersthofer); 8: no moments
};
}  // namespace

void GpuTemporalAccumulator::run(Recorder& rec, const Planes& rp, const Planes& color, float alpha, float momentsAlpha,
                                 int maxHistoryLength, uint32_t luminanceMode, bool cumulativeMoments,
                                 const Planes* sampleMask, const Planes* alphaPlane, const Planes* clipBox,
                                 bool cumulativeColor) {
  const Planes& prev = advance(rec);
  AccumulationPC pc{uint32_t(color.width), uint32_t(color.height), alpha, momentsAlpha, float(maxHistoryLength),
                    luminanceMode, cumulativeMoments};
  pc.options = (alphaPlane ? 1u : 0u) | (clipBox ? 2u : 0u) | (cumulativeColor ? 0u : 4u) | (moments_ ? 0u : 8u);
  const Binding dummy(rec.context().dummy());
  const Binding a = alphaPlane ? Binding(*alphaPlane) : dummy, c = clipBox ? Binding(*clipBox) : dummy;
  rec.dispatch(sampleMask ? "temporal_accumulation_masked" : "temporal_accumulation",
               {rp, color, prev, history_[cur_], sampleMask ? Binding(*sampleMask) : dummy, a, c}, pc, color.width,
               color.height);
}

void GpuTemporalAccumulator::runAdaptive(Recorder& rec, const Planes& rp, const Planes& color, float alpha,
                                         float momentsAlpha, int maxHistoryLength, uint32_t luminanceMode,
                                         const Planes& gradient, int stride, float historyExponent) {
  if (!moments_) throw Error("GpuTemporalAccumulator: runAdaptive() needs the moment planes (resize with moments)");
  const Planes& prev = advance(rec);
  AccumulationPC pc{uint32_t(color.width), uint32_t(color.height), alpha, momentsAlpha, float(maxHistoryLength),
                    luminanceMode, 1, uint32_t(gradient.width), uint32_t(stride), historyExponent};
  const Binding dummy(rec.context().dummy());
  rec.dispatch("temporal_accumulation_gradient", {rp, color, prev, history_[cur_], gradient, dummy, dummy}, pc,
               color.width, color.height);
}

const Planes& GpuTemporalAccumulator::advance(Recorder& rec) {
  const int prev = cur_;
  cur_ ^= 1;
  if (clear_) {
    rec.fill(history_[prev].buffer, 0);
    clear_ = false;
  }
  return history_[prev];
}

void atrousGuide(Recorder& rec, const GpuFrame& frame, float maxDepthSlope, Planes& gradient) {
  atrousGuide(rec, frame[Buffer::Depth], frame.has(Buffer::DepthGradient) ? &frame[Buffer::DepthGradient] : nullptr,
              maxDepthSlope, gradient);
}

void atrousGuide(Recorder& rec, const Planes& depth, const Planes* depthGradient, float maxDepthSlope, Planes& gradient) {
  struct PC {
    uint32_t width, height, hasGradient;
    float maxDepthSlope;
  } pc{uint32_t(depth.width), uint32_t(depth.height), depthGradient != nullptr, maxDepthSlope};
  rec.dispatch("atrous_guide",
               {depth, depthGradient ? Binding(*depthGradient) : Binding(rec.context().dummy()), gradient}, pc,
               depth.width, depth.height);
}

const Planes& emitterGuideNormal(Recorder& rec, const GpuFrame& frame, const EmitterSettings& s, Planes& normal) {
  // As excludeEmitters (src/passes/emitters.cpp): with the setting off, only the emitters whose
  // albedo is no reflectance (above 1).
  const bool all = s.excludeEmitters;
  if (!frame.has(Buffer::Emission) || (!all && !frame.has(Buffer::Albedo))) return frame[Buffer::Normal];
  struct PC {
    uint32_t width, height;
    float threshold;
    uint32_t albedoTest;
  } pc{uint32_t(frame.width), uint32_t(frame.height), s.emitterThreshold, all ? 0u : 1u};
  const Binding albedo = all ? Binding(rec.context().dummy()) : Binding(frame[Buffer::Albedo]);
  rec.dispatch("emitter_guide", {frame[Buffer::Normal], frame[Buffer::Emission], albedo, normal}, pc, frame.width,
               frame.height);
  return normal;
}

void atrousLevel(Recorder& rec, const GpuFrame& frame, const Planes& gradient, const GpuAtrousLevel& lv,
                 const Planes& in, Planes& out) {
  atrousLevel(rec, frame[Buffer::Depth], frame[Buffer::Normal], gradient, lv, in, out);
}

void atrousLevel(Recorder& rec, const Planes& depth, const Planes& normal, const Planes& gradient,
                 const GpuAtrousLevel& lv, const Planes& in, Planes& out) {
  struct PC {
    uint32_t width, height;
    int32_t step, radius;
    float sigmaDepth, depthEpsilon;
    int32_t normalExponent;
    float sigmaLuminance, luminanceEpsilon;
    uint32_t flags, luminanceMode, validPlane;
    float depthEpsilonRelative;
  } pc{uint32_t(in.width), uint32_t(in.height), lv.step, lv.radius, lv.sigmaDepth, lv.depthEpsilon,
       std::max(1, lv.normalExponent), lv.sigmaLuminance, lv.luminanceEpsilon,
       (lv.prefilterVariance ? 1u : 0u) | (lv.varianceScale ? 2u : 0u) | (lv.sigmaScale ? 4u : 0u) |
           (lv.propagateVariance ? 8u : 0u) | (lv.spatialFalloff ? 16u : 0u) | (lv.indirectDistance ? 32u : 0u) |
           (lv.centreScale ? 64u : 0u) | (lv.surfaceKey ? 128u : 0u),
       lv.luminanceMode, uint32_t(lv.validInPlane), lv.depthEpsilonRelative};
  const Binding dummy(rec.context().dummy());
  std::vector<Binding> bindings{depth, normal, gradient, in, out, lv.sigmaScale ? Binding(*lv.sigmaScale) : dummy,
                                lv.spatialFalloff ? Binding(*lv.spatialFalloff) : dummy};
  // The shared tile of atrous.comp (8 x 24^2 floats) where the device has room for it.
  constexpr uint32_t kTileBytes = 8 * 24 * 24 * sizeof(float);
  const bool tiled = lv.sharedTile && rec.context().limits().maxComputeSharedMemorySize >= kTileBytes;
  const Binding key = lv.surfaceKey ? Binding(*lv.surfaceKey) : dummy;  // each variant's last binding
  if (lv.centreScale || lv.indirectDistance) {
    bindings.push_back(lv.indirectDistance ? Binding(*lv.indirectDistance) : dummy);
    bindings.push_back(lv.indirectDistanceScale ? Binding(*lv.indirectDistanceScale) : dummy);
    bindings.push_back(lv.centreScale ? Binding(*lv.centreScale) : dummy);
    bindings.push_back(key);
    rec.dispatch(tiled ? "atrous_glossy" : "atrous_glossy_untiled", bindings, pc, in.width, in.height);
  } else if (lv.validIn && lv.validOut) {
    bindings.push_back(*lv.validIn);
    bindings.push_back(*lv.validOut);
    bindings.push_back(key);
    rec.dispatch(tiled ? "atrous_masked" : "atrous_masked_untiled", bindings, pc, in.width, in.height);
  } else {
    bindings.push_back(key);
    rec.dispatch(tiled ? "atrous" : "atrous_untiled", bindings, pc, in.width, in.height);
  }
}

void gaussian3x3(Recorder& rec, const Planes& in, int srcPlane, Planes& out, int dstPlane) {
  struct PC {
    uint32_t width, height, srcPlane, dstPlane;
  } pc{uint32_t(in.width), uint32_t(in.height), uint32_t(srcPlane), uint32_t(dstPlane)};
  rec.dispatch("gaussian3x3", {in, out}, pc, in.width, in.height);
}

void eyeReproject(Recorder& rec, const GpuFrame& t, const GpuFrame& src, const Planes* valid, int validPlane,
                  const ReprojectionSettings& s, float blend, const Planes& targetLight, const Planes& sourceLight,
                  Planes& out) {
  struct PC {
    uint32_t width, height, flags, validPlane;
    float normalTolerance, depthTolerance, depthGradientScale, blend;
  } pc{uint32_t(t.width), uint32_t(t.height), 0, uint32_t(validPlane), s.normalTolerance, s.depthTolerance,
       s.depthGradientScale, blend};
  // The tests eyeTaps() runs: object ids where both eyes have them.
  if (s.testObjectId && t.has(Buffer::ObjectId) && src.has(Buffer::ObjectId)) pc.flags |= 1;
  if (s.testDepth) pc.flags |= 2;
  if (src.has(Buffer::DepthGradient)) pc.flags |= 4;
  if (valid) pc.flags |= 8;
  const Context& ctx = rec.context();
  rec.dispatch("eye_reprojection",
               {t[Buffer::Position], t[Buffer::Normal], t.bindingOf(Buffer::ObjectId, ctx), src[Buffer::Normal],
                src[Buffer::Depth], src.bindingOf(Buffer::ObjectId, ctx), src.bindingOf(Buffer::DepthGradient, ctx),
                valid ? Binding(*valid) : Binding(ctx.dummy()), src.camera, targetLight, sourceLight, out},
               pc, t.width, t.height);
}

void fxaa(Recorder& rec, const Planes& in, Planes& out, float edgeThreshold, float edgeThresholdMin, float subpixel) {
  struct PC {
    uint32_t width, height;
    float edgeThreshold, edgeThresholdMin, subpixel;
  } pc{uint32_t(in.width), uint32_t(in.height), edgeThreshold, edgeThresholdMin, subpixel};
  rec.dispatch("fxaa", {in, out}, pc, in.width, in.height);
}

void GpuTaa::resize(int w, int h) {
  for (auto& p : history_) p = Planes{};
  linear_ = Planes{};
  width_ = w;
  height_ = h;
  valid_ = false;
}

bool taaSurfaceKeys(Recorder& rec, const GpuFrame& f, const EmitterSettings* emitters, const Planes* cls, Planes& out) {
  const bool object = f.has(Buffer::ObjectId);
  const bool emission = emitters && f.has(Buffer::Emission) && (emitters->excludeEmitters || f.has(Buffer::Albedo));
  if (!object && !cls && !emission) return false;
  if (out.width != f.width || out.height != f.height || out.count != 1) out.allocate(rec.context(), f.width, f.height, 1);
  struct PC {
    uint32_t width, height, hasCls, hasObject, emitters;
    float threshold;
  } pc{uint32_t(f.width), uint32_t(f.height), cls != nullptr, object,
       emission ? (emitters->excludeEmitters ? 1u : 2u) : 0u, emitters ? emitters->emitterThreshold : 0.0f};
  const Context& ctx = rec.context();
  rec.dispatch("taa_keys",
               {cls ? Binding(*cls) : Binding(ctx.dummy()), f.bindingOf(Buffer::ObjectId, ctx),
                f.bindingOf(Buffer::Emission, ctx), f.bindingOf(Buffer::Albedo, ctx), out},
               pc, f.width, f.height);
  return true;
}

const Planes& GpuTaa::run(Recorder& rec, const Planes& rp, const Planes& color, const TaaSettings& s,
                          const Planes* keys) {
  // The first run at this size allocates (valid_ is false: no history is read).
  for (auto& h : history_) allocateOnce(h, rec.context(), width_, height_, 3);
  allocateOnce(linear_, rec.context(), width_, height_, 3);
  const int prev = cur_;
  cur_ ^= 1;
  const TaaParams p = TaaParams::of(s);
  const bool valid = valid_ && display_ == p.display;  // a history in the other domain is no history
  struct PC {
    uint32_t width, height;
    float alpha;
    uint32_t valid, display;
    float crossWeight;
    uint32_t catmullRom, keyed, rejection;
    float subpixelAlpha;
  } pc{uint32_t(color.width), uint32_t(color.height), p.alpha, valid, p.display, p.crossWeight, p.catmullRom,
       s.taaOwnSurface && keys, p.rejection, p.subpixelAlpha};
  rec.dispatch("taa",
               {rp, color, history_[prev], history_[cur_], linear_,
                pc.keyed ? Binding(*keys) : Binding(rec.context().dummy())},
               pc, color.width, color.height);
  valid_ = true;
  display_ = p.display;
  return p.display ? linear_ : history_[cur_];
}

}  // namespace rtd::vk
