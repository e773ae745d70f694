#include "methods/svgf/svgf_reflections.h"

#include <cmath>

#include "core/parallel.h"
#include "passes/demodulation.h"

namespace rtd::svgf {

void Reflections::resize(int /*w*/, int /*h*/, int pad) {
  // Each part's per-frame planes are allocated when the part first runs at this size (prepare,
  // stream; clipBox sizes its own): with none of Voorhuis' parts on, as in plain SVGF and
  // Dundr, none of them is kept (they were ~30 full-frame planes, 112 MB at 1280x720).
  pad_ = pad;
  reflectedGuide_ = {};
  falloff_ = {};
  mirrorKey_ = {};
  virtualDepth_ = {};
  normals_.clear();
  gradient_.clear();
  alpha_ = {};
  for (auto& a : albedo_) a.clear();
  clipLow_ = clipHigh_ = clipScratch_ = {};
  searchFeatures_ = {};
  hasPreviousClasses_ = false;
}

void Reflections::forEachPlane(const PlaneVisitor& visit) const {
  specular_.forEachPlane(visit);
  searchFeatures_.forEachPlane(visit);
  reflectedGuide_.forEachPlane(visit);
  visitPlane(visit, "virtual depth", virtualDepth_);
  for (const Plane& p : normals_) visitPlane(visit, "reflected normal", p);
  for (const Plane& p : gradient_) visitPlane(visit, "virtual depth gradient", p);
  falloff_.visit(visit, "Eq. 6 falloff");
  mirrorKey_.visit(visit, "mirror key");
  visitPlane(visit, "blend floor", alpha_);
  for (const auto& a : albedo_)
    for (const Plane& p : a) visitPlane(visit, "stream albedo", p);
  visitPlanes(visit, "clip low", clipLow_);
  visitPlanes(visit, "clip high", clipHigh_);
  visitPlanes(visit, "clip prefilter", clipScratch_);
}

void Reflections::prepare(const FrameData& f, const FrameData* previous, const SvgfSettings& s,
                          const ReflectionParts& parts, bool lobes, const Reprojection& primary) {
  parts_ = parts;
  lobes_ = lobes;
  motionStats_ = {};
  std::swap(cls_, prevCls_);
  const bool previousClasses = hasPreviousClasses_ && previous;
  hasPreviousClasses_ = parts.classes;
  if (!parts.classes) return;
  const int w = f.width, h = f.height;
  classifySurfaces(f, classThresholds(s), lobes, cls_);
  if (parts.clipping && s.clipOwnSurface) surfaceKeys(f, cls_, surface_);

  if (parts.motion != SpecularMotion::Primary) {
    ReflectionMotionOptions opt;
    opt.search.scaleLdsp = s.ldspScaling;
    opt.search.maxIterations = s.searchIterations;
    opt.search.subpixel = s.subpixelMotion;
    opt.search.fit = s.subpixelFit == SvgfSubpixelFit::quadratic ? SubpixelFit::quadratic : SubpixelFit::inverseDistance;
    opt.mirrors = parts.mirrorMotion;
    opt.glossy = parts.glossyMotion;
    opt.normalTolerance = s.reprojection.normalTolerance;
    rtd::specularReprojection(f, previousClasses ? previous : nullptr, cls_, prevCls_, primary, parts.motion, opt, specular_,
                         &motionStats_, &searchFeatures_);
  }

  if (parts.materialAlpha) {
    if (alpha_.empty()) alpha_.resize(w, h);
    parallelRows(h, [&](int y) {
      float* a = alpha_.row(y);
      for (int x = 0; x < w; ++x)
        a[x] = isSpecular(SurfaceClass(cls_[size_t(y) * w + x])) ? s.alphaSpecular : s.alphaColor;
    });
  }

  if (parts.reflectedFeatures) {
    const bool grad = f.has(Buffer::DepthGradient);
    if (virtualDepth_.empty()) {
      virtualDepth_.resize(w, h);
      normals_.assign(3, Plane(w, h));
      reflectedGuide_.resize(w, h, pad_);
      mirrorKey_.resize(w, h, pad_);
    }
    if (grad && gradient_.empty()) gradient_.assign(2, Plane(w, h));
    // Sec. 4.1: mirror pixels stop on the features of the first non-pure-specular hit: its
    // normal, and the view depth of its virtual image (the primary depth scaled by the whole
    // path length over the primary distance; a mirror showing the sky gets kMissDepth).
    float eye[3];
    const bool haveEye = cameraEye(f.camera, eye);
    const Plane& depth = f.plane(Buffer::Depth);
    parallelRows(h, [&](int y) {
      for (int x = 0; x < w; ++x) {
        const size_t i = size_t(y) * w + x;
        float z = depth.data[i];
        float n[3] = {f.plane(Buffer::Normal, 0).data[i], f.plane(Buffer::Normal, 1).data[i], f.plane(Buffer::Normal, 2).data[i]};
        if (SurfaceClass(cls_[i]) == SurfaceClass::Mirror) {
          float p[3], r[3], t1 = 0, t2 = 0;
          for (int k = 0; k < 3; ++k) {
            n[k] = f.plane(Buffer::ReflectedNormal, k).data[i];
            p[k] = f.plane(Buffer::Position, k).data[i];
            r[k] = f.plane(Buffer::ReflectedPosition, k).data[i];
            t2 += (r[k] - p[k]) * (r[k] - p[k]);
            if (haveEye) t1 += (p[k] - eye[k]) * (p[k] - eye[k]);
          }
          const bool sky = n[0] * n[0] + n[1] * n[1] + n[2] * n[2] < 0.25f;
          t1 = haveEye ? std::sqrt(t1) : z;
          z = sky ? kMissDepth : (t1 > 0.0f ? z * (t1 + std::sqrt(t2)) / t1 : z);
        }
        virtualDepth_.data[i] = z;
        for (int k = 0; k < 3; ++k) normals_[k].data[i] = n[k];
      }
    });
    if (grad) {
      // The frame's exact gradient elsewhere; at mirror pixels the smaller one-sided
      // difference of the virtual depth (as AtrousGuide::build does without a gradient).
      parallelRows(h, [&](int y) {
        const float* zr = virtualDepth_.row(y);
        for (int x = 0; x < w; ++x) {
          const size_t i = size_t(y) * w + x;
          for (int a = 0; a < 2; ++a) gradient_[a].data[i] = f.plane(Buffer::DepthGradient, a).data[i];
          if (SurfaceClass(cls_[i]) != SurfaceClass::Mirror) continue;
          auto smaller = [](float u, float v) { return std::abs(u) < std::abs(v) ? u : v; };
          const float left = x > 0 ? zr[x] - zr[x - 1] : (w > 1 ? zr[x + 1] - zr[x] : 0.0f);
          const float right = x + 1 < w ? zr[x + 1] - zr[x] : left;
          const float up = y > 0 ? zr[x] - virtualDepth_(x, y - 1) : (h > 1 ? virtualDepth_(x, y + 1) - zr[x] : 0.0f);
          const float down = y + 1 < h ? virtualDepth_(x, y + 1) - zr[x] : up;
          gradient_[0].data[i] = smaller(left, right);
          gradient_[1].data[i] = smaller(up, down);
        }
      });
    }
    reflectedGuide_.build(virtualDepth_, normals_, grad ? &gradient_ : nullptr, s.maxDepthSlope);
    // A mirror pixel's virtual depth and reflected normal compare with other mirror pixels'
    // only: across the mirror's outline they would meet the own features of the surfaces
    // around it, and the virtual depth's steep gradient on a curved mirror (the reflected
    // rays fan out) makes w_z accept them at the coarse levels' offsets. The key keeps the
    // two apart in the a-trous levels and the spatial variance (docs/methods/reflections.md,
    // "Mirror pixels keyed apart").
    parallelRows(h, [&](int y) {
      float* k = mirrorKey_.row(y);
      for (int x = 0; x < w; ++x) k[x] = SurfaceClass(cls_[size_t(y) * w + x]) == SurfaceClass::Mirror ? 1.0f : 0.0f;
    });
  }

  if (parts.glossyBandwidth) {
    allocateOnce(falloff_, w, h, pad_);
    const Plane& fp = f.plane(Buffer::ReflectedFootprint);
    parallelRows(h, [&](int y) {
      float* o = falloff_.row(y);
      for (int x = 0; x < w; ++x) {
        const size_t i = size_t(y) * w + x;
        if (SurfaceClass(cls_[i]) != SurfaceClass::GlossyReflection) {
          o[x] = 0.0f;
          continue;
        }
        float omega = s.bandwidthOmega;
        if (s.bandwidthPerLobe) {
          float n2 = 0.0f, t2 = 0.0f;
          for (int k = 0; k < 3; ++k) {
            const float n = f.plane(Buffer::ReflectedNormal, k).data[i];
            const float d = f.plane(Buffer::ReflectedPosition, k).data[i] - f.plane(Buffer::Position, k).data[i];
            n2 += n * n;
            t2 += d * d;
          }
          if (n2 < 0.25f) {  // the mirror ray escapes: the sky's reflection has no detail to keep
            o[x] = 0.0f;
            continue;
          }
          omega *= reflectedLobeWidth(f.plane(Buffer::Roughness).data[i], std::sqrt(t2));
        }
        o[x] = glossySpatialFalloff(glossySpatialSigma(fp.data[i], omega));
      }
    });
  }
}

Reflections::StreamInputs Reflections::stream(const FrameData& f, const StreamPlan& plan, const Reprojection& primary,
                                              const AtrousGuide& primaryGuide, int index) {
  StreamInputs in{&primary, &primaryGuide};
  const std::vector<Plane>* base = plan.demodulated && f.has(plan.albedo) ? &f.planes(plan.albedo) : nullptr;
  in.albedo = base;
  if (!parts_.classes || plan.lobe == Lobe::diffuse) return in;
  if (parts_.motion != SpecularMotion::Primary) in.reprojection = &specular_;
  if (parts_.materialAlpha) in.alpha = &alpha_;
  if (parts_.glossyBandwidth) in.falloff = &falloff_;
  if (!parts_.reflectedFeatures) return in;
  in.guide = &reflectedGuide_;
  in.surfaceKey = &mirrorKey_;
  // Demodulation by primary x reflected albedo at mirror pixels (Sec. 4.1). A specular lobe
  // without its own colour pass is tinted by the albedo of metals only: mix(1, albedo, metalness).
  const int w = f.width, h = f.height;
  const bool tint = !base && plan.lobe == Lobe::specular && f.has(Buffer::Metalness) && f.has(Buffer::Albedo);
  std::vector<Plane>& out = albedo_[index];
  if (out.empty()) out.assign(3, Plane(w, h));
  parallelRows(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const bool mirror = SurfaceClass(cls_[i]) == SurfaceClass::Mirror;
      for (int c = 0; c < 3; ++c) {
        float a = 1.0f;
        if (base) a = (*base)[c].data[i];
        else if (tint) {
          const float m = std::clamp(f.plane(Buffer::Metalness).data[i], 0.0f, 1.0f);
          a = 1.0f + m * (f.plane(Buffer::Albedo, c).data[i] - 1.0f);
        }
        if (mirror) a = demodulationFactor(a) * demodulationFactor(f.plane(Buffer::ReflectedAlbedo, c).data[i]);
        out[c].data[i] = a;
      }
    }
  });
  in.albedo = &out;
  return in;
}

void Reflections::clipBoxes(const Plane3& demod, const StreamPlan& plan, const SvgfSettings& s, const Plane3*& low,
                            const Plane3*& high) {
  low = high = nullptr;
  if (!parts_.clipping || plan.lobe == Lobe::diffuse) return;
  clipMask_.resize(cls_.size());
  for (size_t i = 0; i < cls_.size(); ++i) clipMask_[i] = isSpecular(SurfaceClass(cls_[i]));
  ClipBoxOptions opt;
  opt.sigma = s.clipSigma;
  opt.windowRadius = s.clipWindowRadius;
  clipBox(demod, &clipMask_, opt, clipLow_, clipHigh_, clipScratch_, s.clipOwnSurface ? &surface_ : nullptr);
  low = &clipLow_;
  high = &clipHigh_;
}

const Reprojection& Reflections::taaMotion(const FrameData& f, const Reprojection& primary, bool glossy,
                                           SvgfTaaMirrorHistory mirrors) {
  if (!parts_.classes || parts_.motion == SpecularMotion::Primary) return primary;
  // NoSpecReproj: no TAA on any specular pixel (specular_ has no history there).
  const bool none = parts_.motion == SpecularMotion::None;
  const bool mirrorsFollow = none || mirrors == SvgfTaaMirrorHistory::reflectionMotion;
  if (!lobes_ && (glossy || none) && mirrorsFollow) return specular_;
  if (!f.has(Buffer::Roughness)) return primary;
  const int w = f.width, h = f.height;
  if (taa_.width != w || taa_.height != h) taa_.resize(w, h);
  const float* metal = lobes_ && f.has(Buffer::Metalness) ? f.plane(Buffer::Metalness).ptr() : nullptr;
  parallelRows(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const SurfaceClass c = SurfaceClass(cls_[i]);
      const bool mirror = c == SurfaceClass::Mirror, metallic = !metal || metal[i] >= 0.5f;
      const bool takes = none ? isSpecular(c) : (mirror && mirrorsFollow) || (glossy && c == SurfaceClass::GlossyReflection);
      const bool follow = takes && metallic;
      // The whole record, not only the position: TAA's Catmull-Rom fetch reads which taps the
      // reprojection accepted (kind, base, weights).
      const Reprojection& r = follow ? specular_ : primary;
      taa_.kind[i] = r.kind[i];
      taa_.base[i] = r.base[i];
      taa_.weights[i] = r.weights[i];
      taa_.mask3x3[i] = r.mask3x3[i];
      taa_.prevX.data[i] = r.prevX.data[i];
      taa_.prevY.data[i] = r.prevY.data[i];
      if (!none && mirror && metallic && mirrors == SvgfTaaMirrorHistory::none) taa_.clearHistory(i);
    }
  });
  return taa_;
}

}  // namespace rtd::svgf
