// SVGF-specific passes (Schied et al. 2017 Sec. 4.2 and the variants' changes), exposed for
// the tests. The a-trous filter itself is the shared pass in src/passes/atrous.h.
#pragma once
#include <string>
#include <vector>

#include "passes/atrous.h"
#include "rtd/error.h"
#include "rtd/frame.h"
#include "rtd/methods/svgf.h"

namespace rtd::svgf {

/// What the variance estimate reads for one radiance stream.
struct VarianceInputs {
  const Plane* historyLength = nullptr;  ///< frames, including the current one
  const Plane* moment1 = nullptr;        ///< accumulated E[l]
  const Plane* moment2 = nullptr;        ///< accumulated E[l^2]
  const Plane3* current = nullptr;       ///< this frame's demodulated sample (spatial estimate from luminance)
  const Plane3* accumulated = nullptr;   ///< accumulated colour: the filter's input
  /// Gersthofer Sec. 3.4.3: object ids (padded like the guide) for the mesh-id term of the
  /// spatial estimate; null: no such term.
  const PaddedPlane* objectId = nullptr;
};

struct VarianceParams {
  int shortHistoryFrames = 4;
  SvgfShortHistory shortHistory = SvgfShortHistory::spatialEstimate;
  int radius = 3;                 ///< spatial window (2 radius + 1)^2
  bool fromMoments = false;       ///< Voorhuis: window average of accumulated moments
  float sigmaDepth = 1.0f, depthEpsilon = 1e-2f, depthEpsilonRelative = 0.0f;  ///< AtrousLevel's
  int normalExponent = 128;
  MomentLuminance luminance = MomentLuminance::Rec709;
};

/// w_z's eps from the settings (svgf, asvgf): depthEpsilon + depthEpsilonRelative |z(p)|, the
/// absolute part at least 1e-30 so that a pixel of depth 0 is never 0/0.
inline void setDepthEpsilon(VarianceParams& v, float absolute, float relative) {
  v.depthEpsilon = std::max(absolute, 1e-30f);
  v.depthEpsilonRelative = relative;
}

/// Level-0 input of the filter: out.color = accumulated colour, out.lum its luminance, out.var
/// = max(0, mu2 - mu1^2) where the history length n >= shortHistoryFrames; where it is shorter
/// and the mode is spatialEstimate, the depth/normal-weighted window estimate
/// E_w[l^2] - E_w[l]^2 (l: current luminance, or the accumulated moments). Returns the number
/// of pixels that used the spatial estimate.
/// `scratch` (two planes of the guide's geometry) holds the window's inputs.
size_t estimateVariance(const AtrousGuide& guide, const VarianceInputs& in, const VarianceParams& p, AtrousImage& out,
                        PaddedPlane scratch[2]);
/// estimateVariance in two parts: its rows [rowBegin, rowEnd) (out's colour, luminance and
/// temporal variance, the window's inputs; returns how many of their pixels have a short
/// history), from any thread, then, once every row is done, the spatial estimate where
/// `shortCount` (the rows' sum) is not 0 (returns the pixels that used it).
size_t varianceRows(const VarianceInputs& in, const VarianceParams& p, AtrousImage& out, PaddedPlane scratch[2],
                    int rowBegin, int rowEnd);
size_t spatialVarianceEstimate(const AtrousGuide& guide, const VarianceInputs& in, const VarianceParams& p,
                               AtrousImage& out, PaddedPlane scratch[2], size_t shortCount);

/// Per-pixel multiplier of sigma_l: 0 where w_l is off (Dundr, short history), Voorhuis Eq. 8
/// where enabled, else 1.
void luminanceSigmaScale(const Plane& historyLength, const SvgfSettings& s, PaddedPlane& out);

/// Share of the visible pixels (`hidden` 0; all where null) that `mask` marks as sampled
/// (SampleMask != 0): exactly 1 only where every visible pixel is sampled, which makes the
/// progressive mode (Dundr Sec. 5, Gersthofer's masking) the plain pipeline.
float sampleCoverage(const Plane& mask, const Plane* hidden);

/// 3x3 per-channel median (Voorhuis Sec. 6, fireflies) of pixels whose roughness is >= 0.9
/// (diffuse), or of every pixel when `roughness` is null; others are copied.
void median3x3(const Plane3& in, const Plane* roughness, Plane3& out);

/// The executed tap spacings for `iterations` levels in `order`.
void levelSteps(SvgfLevelOrder order, int iterations, int* steps);

/// Buffers SVGF reads beyond its required ones and the shared passes' (both backends): the
/// split radiance streams, roughness (firefly median), the depth gradient (the a-trous guide,
/// whatever the reprojection tests), with useSampleMask the sample mask, and the buffers of
/// the Voorhuis parts that are not off.
inline std::vector<Buffer> extraBuffers(const SvgfSettings& s) {
  std::vector<Buffer> b{Buffer::Direct,   Buffer::Indirect,  Buffer::Diffuse,      Buffer::Specular,
                        Buffer::Roughness, Buffer::DepthGradient, Buffer::DiffuseAlbedo, Buffer::SpecularAlbedo};
  if (s.components == SvgfComponents::composite)
    for (Buffer g : {Buffer::IndirectDiffuse, Buffer::SecondaryDistance, Buffer::Metalness, Buffer::ObjectId,
                     Buffer::Position})
      b.push_back(g);
  if (s.useSampleMask) b.push_back(Buffer::SampleMask);
  if (s.taa.taaOwnSurface) b.push_back(Buffer::ObjectId);  // the own-surface box's keys (passes/taa_keys.h)
  // Voorhuis' parts (svgf_reflections.h): pixel classes and the reflection buffers.
  const bool reflections = s.specularMotion != SvgfSpecularMotion::primary || s.reflectedFeatures != SvgfPart::off ||
                           s.glossyBandwidth != SvgfPart::off || s.neighbourhoodClipping != SvgfPart::off ||
                           s.materialAlpha != SvgfPart::off;
  if (reflections)
    for (Buffer r : {Buffer::Metalness, Buffer::Position, Buffer::ReflectedPosition, Buffer::ReflectedNormal,
                     Buffer::ReflectedAlbedo, Buffer::SecondaryDistance, Buffer::MirrorDirection, Buffer::ReflectedFootprint})
      b.push_back(r);
  return b;
}

/// Which light a stream holds, for Voorhuis' per-class treatment: everything at the pixel
/// (Color, Direct, Indirect), or one BSDF lobe (Diffuse, Specular).
enum class Lobe : uint8_t { all, diffuse, specular };

/// At most two radiance streams (direct and indirect, or diffuse and specular) per view.
inline constexpr int kMaxStreams = 2;

/// One radiance stream SVGF filters separately (Schied et al. 2017: direct and indirect).
struct StreamPlan {
  Buffer buffer;
  const char* name;
  bool demodulated;  ///< divided by albedo (not the specular stream: it carries its own tint)
  bool indirect;     ///< Voorhuis: no per-level variance filtering
  Lobe lobe = Lobe::all;
  /// The stream's own demodulation colour where the frame has it (Blender's DiffCol /
  /// GlossCol passes: Buffer::DiffuseAlbedo, Buffer::SpecularAlbedo); Albedo otherwise.
  Buffer albedo = Buffer::Albedo;
  /// false: added to the output as it comes, neither accumulated nor filtered (the specular
  /// lobe under components = diffuse).
  bool filtered = true;
};

/// The streams of a frame under the `components` setting; `has(b)` says whether the frame has
/// buffer b. `preferLobes`: auto picks Diffuse+Specular before Direct+Indirect. Throws
/// rtd::Error when an explicit choice needs a buffer the frame lacks. Shared by the CPU and
/// Vulkan implementations.
template <class Has> int planStreams(SvgfComponents c, Has has, StreamPlan out[2], bool preferLobes = false) {
  if (c == SvgfComponents::lobes)
    c = has(Buffer::Diffuse) && has(Buffer::Specular) ? SvgfComponents::diffuseSpecular : SvgfComponents::color;
  if (c == SvgfComponents::automatic) {
    const bool lobes = has(Buffer::Diffuse) && has(Buffer::Specular);
    if (lobes && preferLobes) c = SvgfComponents::diffuseSpecular;
    else if (has(Buffer::Direct) && has(Buffer::Indirect)) c = SvgfComponents::directIndirect;
    else if (lobes) c = SvgfComponents::diffuseSpecular;
    else c = SvgfComponents::color;
  }
  auto need = [&](Buffer b) {
    if (!has(b)) throw Error("svgf: components setting needs buffer '" + std::string(bufferName(b)) + "', absent from the frame");
  };
  switch (c) {
    case SvgfComponents::diffuse:
      // A literal reading of Dundr Sec. 4.1: only the diffuse light is filtered; without the
      // split, the whole colour divided by the albedo is the approximate diffuse component.
      if (!(has(Buffer::Diffuse) && has(Buffer::Specular))) break;
      out[0] = {Buffer::Diffuse, "diffuse", true, false, Lobe::diffuse,
                has(Buffer::DiffuseAlbedo) ? Buffer::DiffuseAlbedo : Buffer::Albedo};
      out[1] = {Buffer::Specular, "specular", false, false, Lobe::specular, Buffer::Albedo, false};
      return 2;
    case SvgfComponents::directIndirect:
      need(Buffer::Direct);
      need(Buffer::Indirect);
      out[0] = {Buffer::Direct, "direct", true, false};
      out[1] = {Buffer::Indirect, "indirect", true, true};
      return 2;
    case SvgfComponents::diffuseSpecular: {
      need(Buffer::Diffuse);
      need(Buffer::Specular);
      const bool diffuseAlbedo = has(Buffer::DiffuseAlbedo), specularAlbedo = has(Buffer::SpecularAlbedo);
      out[0] = {Buffer::Diffuse, "diffuse", true, false, Lobe::diffuse,
                diffuseAlbedo ? Buffer::DiffuseAlbedo : Buffer::Albedo};
      out[1] = {Buffer::Specular, "specular", specularAlbedo, false, Lobe::specular,
                specularAlbedo ? Buffer::SpecularAlbedo : Buffer::Albedo};
      return 2;
    }
    default: break;
  }
  out[0] = {Buffer::Color, "color", true, false};
  return 1;
}

}  // namespace rtd::svgf
