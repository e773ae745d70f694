#if defined(RTD_HAS_VULKAN)
#include "methods/svgf/svgf_reflections_vulkan.h"

#include "passes/neighbourhood_clipping.h"

namespace rtd::svgf {

void GpuReflections::resize(vk::Context& /*ctx*/, int /*w*/, int /*h*/) {
  // As on the CPU (Reflections::resize): the ~50 planes are allocated when the parts first run
  // at this size (allocate, from prepare), so plain SVGF and Dundr keep none of them (184 MB
  // of device memory at 1280x720).
  *this = GpuReflections();
}

void GpuReflections::allocate(vk::Context& ctx, int w, int h) {
  for (auto& c : cls_) c.allocate(ctx, w, h, 1);
  specular_.allocate(ctx, w, h, 8);
  taa_.allocate(ctx, w, h, 8);
  guideDepth_.allocate(ctx, w, h, 1);
  guideNormal_.allocate(ctx, w, h, 3);
  gradientIn_.allocate(ctx, w, h, 2);
  gradient_.allocate(ctx, w, h, 2);
  alpha_.allocate(ctx, w, h, 1);
  falloff_.allocate(ctx, w, h, 1);
  mirrorKey_.allocate(ctx, w, h, 1);
  for (auto& a : albedo_) a.allocate(ctx, w, h, 3);
  clip_.allocate(ctx, w, h, 6);
  clipRows_.allocate(ctx, w, h, 6);
  clipBlur_.allocate(ctx, w, h, 3);
}

void GpuReflections::prepare(vk::Recorder& rec, const vk::GpuFrame& f, const vk::GpuFrame* previous,
                             const SvgfSettings& s, const ReflectionParts& parts, bool lobes, const vk::Planes& primary) {
  parts_ = parts;
  lobes_ = lobes;
  cur_ ^= 1;
  const bool previousClasses = hasPreviousClasses_ && previous && previous->width == f.width && previous->height == f.height;
  hasPreviousClasses_ = parts.classes;
  if (!parts.classes) return;
  if (cls_[0].buffer.empty()) allocate(rec.context(), f.width, f.height);
  const vk::Context& ctx = rec.context();
  const uint32_t w = uint32_t(f.width), h = uint32_t(f.height);
  hasObjectId_ = f.has(Buffer::ObjectId);
  objectId_ = f.bindingOf(Buffer::ObjectId, ctx);
  {
    struct PC {
      uint32_t width, height;
      float pureSpecular, reflection, diffuse;
      uint32_t specularLobe, hasRoughness, hasMetalness;
    } pc{w, h, s.pureSpecularRoughness, s.reflectionRoughness, s.diffuseRoughness, lobes, f.has(Buffer::Roughness),
         f.has(Buffer::Metalness)};
    rec.dispatch("surface_class",
                 {f[Buffer::Normal], f.bindingOf(Buffer::Roughness, ctx), f.bindingOf(Buffer::Metalness, ctx), cls_[cur_]},
                 pc, f.width, f.height);
  }
  if (parts.motion != SpecularMotion::Primary) {
    const bool usable = previousClasses;
    const vk::GpuFrame& p = usable ? *previous : f;
    auto both = [&](Buffer b) { return f.has(b) && p.has(b); };
    enum : uint32_t { kMirrors = 1, kGlossy = 2, kReflectedNormal = 4, kSkyDirection = 8, kScale = 16, kSubpixel = 32,
                      kQuadratic = 64 };
    uint32_t flags = (s.ldspScaling ? kScale : 0u) | (s.subpixelMotion ? kSubpixel : 0u) |
                     (s.subpixelFit == SvgfSubpixelFit::quadratic ? kQuadratic : 0u);
    if (parts.mirrorMotion && both(Buffer::ReflectedPosition)) flags |= kMirrors;
    if (parts.glossyMotion && both(Buffer::Position) && both(Buffer::MirrorDirection) && both(Buffer::SecondaryDistance))
      flags |= kGlossy;
    if (both(Buffer::ReflectedNormal)) flags |= kReflectedNormal;
    if (both(Buffer::MirrorDirection) && both(Buffer::Position)) flags |= kSkyDirection;
    struct PC {
      uint32_t width, height, mode, flags;
      int32_t maxIterations;
      float normalTolerance;
    } pc{w, h, usable ? (parts.motion == SpecularMotion::None ? 1u : 2u) : 0u, flags, s.searchIterations,
         s.reprojection.normalTolerance};
    rec.dispatch("reflection_reproject",
                 {primary, specular_, cls_[cur_], cls_[cur_ ^ 1], f.bindingOf(Buffer::ReflectedPosition, ctx),
                  f.bindingOf(Buffer::ReflectedNormal, ctx), p.bindingOf(Buffer::ReflectedPosition, ctx),
                  p.bindingOf(Buffer::ReflectedNormal, ctx), f.bindingOf(Buffer::Position, ctx),
                  f.bindingOf(Buffer::MirrorDirection, ctx), f.bindingOf(Buffer::SecondaryDistance, ctx),
                  p.bindingOf(Buffer::Position, ctx), p.bindingOf(Buffer::MirrorDirection, ctx),
                  p.bindingOf(Buffer::SecondaryDistance, ctx)},
                 pc, f.width, f.height);
  }
  if (parts.materialAlpha || parts.glossyBandwidth || parts.reflectedFeatures) {
    float eye[3] = {0, 0, 0};
    const bool haveEye = cameraEye(f.cameraValue, eye);
    struct PC {
      uint32_t width, height, flags;
      float alphaColor, alphaSpecular, omega, eyeX, eyeY, eyeZ;
    } pc{w, h,
         (parts.materialAlpha ? 1u : 0u) | (parts.glossyBandwidth ? 2u : 0u) | (parts.reflectedFeatures ? 4u : 0u) |
             (haveEye ? 8u : 0u) | (parts.glossyBandwidth && s.bandwidthPerLobe ? 16u : 0u),
         s.alphaColor, s.alphaSpecular, s.bandwidthOmega, eye[0], eye[1], eye[2]};
    rec.dispatch("voorhuis_features",
                 {cls_[cur_], f[Buffer::Normal], f[Buffer::Depth], f.bindingOf(Buffer::Position, ctx),
                  f.bindingOf(Buffer::ReflectedPosition, ctx), f.bindingOf(Buffer::ReflectedNormal, ctx),
                  f.bindingOf(Buffer::ReflectedFootprint, ctx), alpha_, falloff_, guideDepth_, guideNormal_,
                  f.bindingOf(Buffer::Roughness, ctx), mirrorKey_},
                 pc, f.width, f.height);
  }
  if (parts.reflectedFeatures) {
    const bool grad = f.has(Buffer::DepthGradient);
    if (grad) {
      struct PC {
        uint32_t width, height;
      } pc{w, h};
      rec.dispatch("voorhuis_gradient", {cls_[cur_], guideDepth_, f[Buffer::DepthGradient], gradientIn_}, pc, f.width,
                   f.height);
    }
    vk::atrousGuide(rec, guideDepth_, grad ? &gradientIn_ : nullptr, s.maxDepthSlope, gradient_);
  }
}

GpuReflections::StreamInputs GpuReflections::stream(vk::Recorder& rec, const vk::GpuFrame& f, const StreamPlan& plan,
                                                    const vk::Planes& primary, const GpuGuide& primaryGuide,
                                                    int index) {
  StreamInputs in{&primary, primaryGuide};
  const vk::Planes* base = plan.demodulated && f.has(plan.albedo) ? &f[plan.albedo] : nullptr;
  in.albedo = base;
  if (!parts_.classes || plan.lobe == Lobe::diffuse) return in;
  if (parts_.motion != SpecularMotion::Primary) in.reprojection = &specular_;
  if (parts_.materialAlpha) in.alpha = &alpha_;
  if (parts_.glossyBandwidth) in.falloff = &falloff_;
  if (!parts_.reflectedFeatures) return in;
  in.guide = {&guideDepth_, &guideNormal_, &gradient_};
  in.surfaceKey = &mirrorKey_;
  const vk::Context& ctx = rec.context();
  const bool tint = !base && plan.lobe == Lobe::specular && f.has(Buffer::Metalness) && f.has(Buffer::Albedo);
  struct PC {
    uint32_t width, height, hasBase, tint;
  } pc{uint32_t(f.width), uint32_t(f.height), base != nullptr, tint};
  rec.dispatch("voorhuis_albedo",
               {cls_[cur_], base ? vk::Binding(*base) : vk::Binding(ctx.dummy()), f.bindingOf(Buffer::Albedo, ctx),
                f.bindingOf(Buffer::Metalness, ctx), f.bindingOf(Buffer::ReflectedAlbedo, ctx), albedo_[index]},
               pc, f.width, f.height);
  in.albedo = &albedo_[index];
  return in;
}

const vk::Planes* GpuReflections::clipBox(vk::Recorder& rec, const vk::Planes& demod, const StreamPlan& plan,
                                          const SvgfSettings& s) {
  if (!parts_.clipping || plan.lobe == Lobe::diffuse) return nullptr;
  struct PC {
    uint32_t width, height, mode;
    int32_t radius;
    uint32_t masked;
    float weights[7];
    uint32_t hasObject;
  } pc{uint32_t(demod.width), uint32_t(demod.height), 0, 3, 0, {}, hasObjectId_};
  clipGaussianWeights(3, s.clipSigma, pc.weights);
  const vk::Binding dummy(rec.context().dummy());
  if (s.clipOwnSurface) {  // the pixel's own surface: clipBoxOnSurfaces
    const vk::Binding obj = hasObjectId_ ? objectId_ : dummy;
    pc.mode = 4;
    rec.dispatch("clip_box", {demod, clipBlur_, cls_[cur_], obj}, pc, demod.width, demod.height);
    pc.mode = 5;
    pc.radius = s.clipWindowRadius;
    rec.dispatch("clip_box", {clipBlur_, clip_, cls_[cur_], obj}, pc, demod.width, demod.height);
    return &clip_;
  }
  rec.dispatch("clip_box", {demod, clipRows_, dummy, dummy}, pc, demod.width, demod.height);
  pc.mode = 1;
  rec.dispatch("clip_box", {clipRows_, clipBlur_, dummy, dummy}, pc, demod.width, demod.height);
  pc.mode = 2;
  pc.radius = s.clipWindowRadius;
  rec.dispatch("clip_box", {clipBlur_, clipRows_, dummy, dummy}, pc, demod.width, demod.height);
  pc.mode = 3;
  pc.masked = 1;
  rec.dispatch("clip_box", {clipRows_, clip_, cls_[cur_], dummy}, pc, demod.width, demod.height);
  return &clip_;
}

const vk::Planes& GpuReflections::taaMotion(vk::Recorder& rec, const vk::GpuFrame& f, const vk::Planes& primary,
                                            bool glossy, SvgfTaaMirrorHistory mirrors) {
  if (!parts_.classes || parts_.motion == SpecularMotion::Primary) return primary;
  const bool none = parts_.motion == SpecularMotion::None;  // NoSpecReproj: no TAA on specular pixels
  const bool mirrorsFollow = none || mirrors == SvgfTaaMirrorHistory::reflectionMotion;
  if (!lobes_ && (glossy || none) && mirrorsFollow) return specular_;
  if (!f.has(Buffer::Roughness)) return primary;
  struct PC {
    uint32_t width, height, hasMetal, mode, mirrors;
  } pc{uint32_t(f.width), uint32_t(f.height), lobes_ && f.has(Buffer::Metalness), none ? 2u : glossy ? 1u : 0u,
       none ? 0u : uint32_t(mirrors)};
  rec.dispatch("voorhuis_taa_motion",
               {cls_[cur_], f.bindingOf(Buffer::Metalness, rec.context()), primary, specular_, taa_}, pc, f.width,
               f.height);
  return taa_;
}

}  // namespace rtd::svgf
#endif
