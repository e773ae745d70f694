// SVGF's Voorhuis mode (Voorhuis 2018, Sec. 4 and 7): which of its parts run for a frame, and
// the CPU state that feeds the per-stream SVGF passes: surface classes, the specular
// reprojection (diamond search), guide features of the reflected geometry, Eq. 6 falloff,
// per-class blend factors and neighbourhood-clipping boxes. The shared passes it drives live
// in src/passes/ (diamond_search, reflection_reprojection, neighbourhood_clipping);
// docs/methods/reflections.md describes the whole.
#pragma once
#include <algorithm>
#include <string>
#include <vector>

#include "core/frame_data.h"
#include "methods/svgf/svgf_passes.h"
#include "passes/atrous.h"
#include "passes/neighbourhood_clipping.h"
#include "passes/reflection_reprojection.h"

namespace rtd::svgf {

/// The Voorhuis parts that run on a frame, resolved from the settings and the frame's buffers.
struct ReflectionParts {
  bool classes = false;           ///< pixels are classed (any part below is on)
  SpecularMotion motion = SpecularMotion::Primary;
  bool mirrorMotion = false, glossyMotion = false;  ///< which classes search (motion == Reflection)
  bool reflectedFeatures = false;
  bool glossyBandwidth = false;
  bool clipping = false;
  bool materialAlpha = false;
  /// Parts that were asked for ("auto") but are off for this frame, and why.
  std::vector<std::string> notes;
};

/// Resolves the parts. `lobes`: the frame is filtered as diffuse / specular lobes. An `on`
/// part (or specularMotion = reflection) whose buffers the frame lacks is an rtd::Error naming
/// the first missing buffer; an `auto` part is then off with a note.
template <class Has> ReflectionParts resolveReflectionParts(const SvgfSettings& s, Has has, bool lobes) {
  ReflectionParts p;
  auto missing = [&](std::initializer_list<Buffer> need) -> const char* {
    for (Buffer b : need)
      if (!has(b)) return bufferName(b).data();
    return nullptr;
  };
  // Returns whether the part runs; an explicit request without its buffers throws.
  auto decide = [&](const char* part, bool requested, bool required, std::initializer_list<Buffer> need) {
    if (!requested) return false;
    const char* m = missing(need);
    if (!m) return true;
    if (required) throw Error(std::string("svgf: ") + part + " needs buffer '" + m + "', absent from the frame");
    p.notes.push_back(std::string(part) + " off: the frame has no '" + m + "' buffer");
    return false;
  };
  // Parts that need only the pixel classes: from Roughness, or from the lobe split alone.
  auto classed = [&](const char* part, SvgfPart mode) {
    if (mode == SvgfPart::off) return false;
    if (lobes || has(Buffer::Roughness)) return true;
    if (mode == SvgfPart::on)
      throw Error(std::string("svgf: ") + part + " needs buffer 'roughness' (or the diffuse / specular split), absent from the frame");
    p.notes.push_back(std::string(part) + " off: the frame has no 'roughness' buffer and no diffuse / specular split");
    return false;
  };
  p.clipping = classed("neighbourhoodClipping", s.neighbourhoodClipping);
  p.materialAlpha = classed("materialAlpha", s.materialAlpha);
  switch (s.specularMotion) {
    case SvgfSpecularMotion::primary: break;
    case SvgfSpecularMotion::none:
      if (classed("specularMotion=none", SvgfPart::automatic)) p.motion = SpecularMotion::None;
      break;
    case SvgfSpecularMotion::reflection:
    case SvgfSpecularMotion::automatic: {
      const bool req = s.specularMotion == SvgfSpecularMotion::reflection;
      p.mirrorMotion = decide("reflection motion (mirrors)", true, req, {Buffer::Roughness, Buffer::ReflectedPosition});
      p.glossyMotion = decide("reflection motion (glossy)", true, req,
                              {Buffer::Roughness, Buffer::Position, Buffer::MirrorDirection, Buffer::SecondaryDistance});
      if (p.mirrorMotion || p.glossyMotion) p.motion = SpecularMotion::Reflection;
      break;
    }
  }
  p.reflectedFeatures = decide("reflectedFeatures", s.reflectedFeatures != SvgfPart::off, s.reflectedFeatures == SvgfPart::on,
                               {Buffer::Roughness, Buffer::ReflectedPosition, Buffer::ReflectedNormal, Buffer::ReflectedAlbedo});
  // Eq. 6 in world units reads the footprint; in lobe widths also the reflected hit's distance.
  const std::initializer_list<Buffer> bandwidthWorld = {Buffer::Roughness, Buffer::ReflectedFootprint};
  const std::initializer_list<Buffer> bandwidthLobe = {Buffer::Roughness, Buffer::ReflectedFootprint, Buffer::Position,
                                                       Buffer::ReflectedPosition, Buffer::ReflectedNormal};
  p.glossyBandwidth = decide("glossyBandwidth", s.glossyBandwidth != SvgfPart::off, s.glossyBandwidth == SvgfPart::on,
                             s.bandwidthPerLobe ? bandwidthLobe : bandwidthWorld);
  p.classes = p.clipping || p.materialAlpha || p.motion != SpecularMotion::Primary || p.reflectedFeatures ||
              p.glossyBandwidth;
  return p;
}

/// Camera position from a row-major world-to-camera matrix [R | t]: -R^T t; false without a camera.
inline bool cameraEye(const Camera& c, float eye[3]) {
  if (!c.valid) return false;
  const auto& m = c.worldToCamera;
  for (int k = 0; k < 3; ++k) eye[k] = -(m[0 * 4 + k] * m[3] + m[1 * 4 + k] * m[7] + m[2 * 4 + k] * m[11]);
  return true;
}

/// Width of a glossy pixel's reflected lobe where it lands, world units: 2 alpha t, alpha =
/// roughness^2 the GGX width of the half-vector lobe (the renderer's parameterisation,
/// Buffer::Roughness is perceptual), doubled by the reflection, over the distance t to the
/// representative ray's hit. Eq. 6's omega in these units (SvgfSettings::bandwidthPerLobe)
/// compares the pixel footprint at the hit with the blur of the reflection there. Never below
/// 1e-30, so that omega stays positive.
inline float reflectedLobeWidth(float roughness, float hitDistance) {
  const float r = std::clamp(roughness, 0.0f, 1.0f);
  return std::max(2.0f * r * r * std::max(0.0f, hitDistance), 1e-30f);
}

inline SurfaceClassThresholds classThresholds(const SvgfSettings& s) {
  return {s.pureSpecularRoughness, s.reflectionRoughness, s.diffuseRoughness};
}

/// The CPU side of the Voorhuis mode for one frame (svgf.cpp drives it).
class Reflections {
 public:
  /// A new frame size: drops the per-frame planes, which each part allocates at the frame's
  /// size when it first runs (none are kept while no part is on).
  void resize(int w, int h, int pad);
  void reset() { hasPreviousClasses_ = false; }

  /// Classes, the specular reprojection and guide, the falloff plane: once per frame, after
  /// the primary reprojection. `lobes`: the frame is filtered as lobes.
  void prepare(const FrameData& frame, const FrameData* previous, const SvgfSettings& s, const ReflectionParts& parts,
               bool lobes, const Reprojection& primary);

  /// What one stream reads (primary inputs for the diffuse lobe).
  struct StreamInputs {
    const Reprojection* reprojection;
    const AtrousGuide* guide;
    const Plane* alpha = nullptr;            ///< per-pixel blend floor, or null
    const PaddedPlane* falloff = nullptr;    ///< Eq. 6 falloff, or null
    const PaddedPlane* surfaceKey = nullptr; ///< with the reflected guide: 1 at mirror pixels, 0 elsewhere
    const std::vector<Plane>* albedo;        ///< demodulation colour, or null (not demodulated)
  };
  StreamInputs stream(const FrameData& frame, const StreamPlan& plan, const Reprojection& primary,
                      const AtrousGuide& primaryGuide, int index);
  /// Neighbourhood-clipping box of a stream's demodulated sample (null when the stream is not clipped).
  void clipBoxes(const Plane3& demod, const StreamPlan& plan, const SvgfSettings& s, const Plane3*& low,
                 const Plane3*& high);
  /// The reprojection TAA follows: mirror pixels (and GlossyReflection ones with
  /// `glossy`, SvgfSettings::taaGlossyReflectionMotion) take the specular one where the
  /// specular light dominates them (every such pixel of a single stream; metallic ones of a
  /// lobe split); `mirrors` (SvgfSettings::taaMirrorHistory) may give the mirror pixels the
  /// primary record or none (no history: TAA keeps the current colour).
  const Reprojection& taaMotion(const FrameData& frame, const Reprojection& primary, bool glossy,
                                SvgfTaaMirrorHistory mirrors = SvgfTaaMirrorHistory::reflectionMotion);

  /// Every float plane it owns (PlaneVisitor).
  void forEachPlane(const PlaneVisitor& visit) const;

  const ReflectionParts& parts() const { return parts_; }
  const PixelVector<uint8_t>& classes() const { return cls_; }
  const ReflectionMotionStats& motionStats() const { return motionStats_; }
  const Reprojection& specularReprojection() const { return specular_; }

 private:
  ReflectionParts parts_;
  int pad_ = 0;  ///< the a-trous border of the padded planes (resize)
  bool lobes_ = false, hasPreviousClasses_ = false;
  PixelVector<uint8_t> cls_, prevCls_, clipMask_;
  PixelVector<uint32_t> surface_;  ///< clipping's surface keys (surfaceKeys)
  Reprojection specular_, taa_;
  ReflectionSearchFeatures searchFeatures_;  ///< the previous frame's, for the diamond search
  AtrousGuide reflectedGuide_;
  Plane virtualDepth_;
  std::vector<Plane> normals_, gradient_;
  PaddedPlane falloff_, mirrorKey_;
  Plane alpha_;
  std::vector<Plane> albedo_[2];
  Plane3 clipLow_, clipHigh_, clipScratch_;
  ReflectionMotionStats motionStats_;
};

}  // namespace rtd::svgf
