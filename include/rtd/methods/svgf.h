// rtdenoise — method "svgf": spatiotemporal variance-guided filtering (Schied et al. 2017) with
// the variants of Dundr (progressive SVGF), Gersthofer (VR stereo) and Voorhuis (reflections).
// docs/methods/svgf.md describes the pipeline, every setting's source and every unclear point.
#pragma once
#include <string_view>

#include "rtd/methods/emitters.h"
#include "rtd/methods/reprojection.h"
#include "rtd/methods/taa.h"

namespace rtd {

/// Which paper's choices the variant-controlled settings start from. voorhuis is the whole
/// method of Voorhuis 2018 ("Ours"); voorhuisBase and voorhuisNoSpecReproj are the paper's two
/// baselines (Sec. 7.1); voorhuisRobustness only its Sec. 6 robustness changes.
enum class SvgfVariant { schied, dundr, gersthofer, voorhuis, voorhuisBase, voorhuisNoSpecReproj, voorhuisRobustness };
/// A-trous kernel: 5x5 B3 spline (Schied, Dammertz) or 3x3 binomial (Dundr Fig. 4).
enum class SvgfKernel { b3spline5x5, binomial3x3 };
/// Which radiance streams are filtered separately and summed; `composite` (Gersthofer Sec.
/// 3.3): indirect diffuse (Buffer::IndirectDiffuse) and the rest of Color (direct + indirect
/// specular) are accumulated separately, the indirect diffuse median-filtered and shared
/// between the eyes, then the two are added and filtered as one stream.
/// `diffuse` (a literal reading of Dundr Sec. 4.1): only the diffuse lobe (Buffer::Diffuse) is
/// filtered, the specular lobe added unfiltered; Color as one stream where the frame lacks the
/// split. `lobes`: the diffuse and specular lobes as two streams where the frame has them (each
/// demodulated by its own colour pass where it has one, as diffuseSpecular), Color as one
/// stream otherwise. The dundr preset uses `lobes`: the diffuse light as the tracer outputs it
/// where it does (his "ideally"), colour / albedo where it does not (his fallback)
/// (docs/methods/svgf.md, "Dundr's stream").
enum class SvgfComponents { automatic, color, directIndirect, diffuseSpecular, composite, diffuse, lobes };
/// The last step of the output (Gersthofer Sec. 3.5): none (linear radiance, the library's
/// contract) or the ACES filmic curve (Narkowicz fit), display-referred [0, 1].
enum class SvgfToneMap { none, aces };
/// Order of the a-trous steps: 1,2,4,... (Schied) or 1 then coarse to fine 16,8,4,2 (Dundr Sec. 4.4).
enum class SvgfLevelOrder { fineToCoarse, firstThenCoarseToFine, coarseToFine };
/// What scales the luminance difference in w_l: sigma_l * sqrt(Var) (Schied) or sigma_l * Var (Dundr).
enum class SvgfLuminanceScale { standardDeviation, variance };
/// Variance while the history is short: 7x7 spatial estimate (Schied), luminance weight off
/// (Dundr's "turn off the weight entirely"), or the temporal moments regardless.
enum class SvgfShortHistory { spatialEstimate, disableLuminanceWeight, temporal };
/// The luminance of moments, variance and w_l.
enum class SvgfLuminance { rec709, rec601, cieLightness };
/// When the 3x3 Gaussian prefilter g3x3 of the variance runs: before every level (Schied Eq. 5),
/// once before the first level (Dundr Sec. 4.3), or never.
enum class SvgfVariancePrefilter { everyLevel, once, off };
/// A part of Voorhuis' pipeline that reads buffers some inputs lack (reflection features,
/// roughness): off; on (an error naming the buffer when the frame lacks one); auto (on where
/// the frame has the buffers, otherwise off, said in FrameStats::notes).
enum class SvgfPart { off, on, automatic };
/// What specular pixels (roughness < diffuseRoughness) reproject with: the primary hit's
/// motion (Base), nothing, with no TAA either (NoSpecReproj), the reflected geometry's motion
/// by diamond search (Voorhuis Sec. 4; an error without its buffers), or reflection where the
/// buffers allow and the primary motion elsewhere (auto).
/// Subpixel refinement of reflection motion (rtd::SubpixelFit, src/passes/diamond_search.h):
/// Voorhuis Eqs. 2-3, or the minimum of the quadratic through the 3x3's squared distances.
enum class SvgfSubpixelFit { inverseDistance, quadratic };
/// The history TAA takes on mirror pixels in the Voorhuis mode (the paper does not say whether
/// Ours runs TAA there with the reflection motion; docs/methods/reflections.md, "TAA on mirrors").
enum class SvgfTaaMirrorHistory { reflectionMotion, primaryMotion, none };
enum class SvgfSpecularMotion { primary, none, reflection, automatic };

struct SvgfSettings {
  static constexpr const char* kMethod = "svgf";

  /// Preset of the paper-specific fields below (marked "variant"); setting it by name resets
  /// them to that paper's defaults, individual fields set afterwards override the preset.
  SvgfVariant variant = SvgfVariant::schied;
  /// auto: Direct+Indirect if the frame has both, else Diffuse+Specular, else Color.
  SvgfComponents components = SvgfComponents::automatic;

  // --- temporal accumulation (Schied Sec. 4.1) ---
  /// Colour blend floor, w = max(1/n, alpha) (Schied 0.2; Dundr "around 0.1"). [variant]
  float alphaColor = 0.2f;
  /// Moments blend (Schied 0.2). [variant]
  float alphaMoments = 0.2f;
  /// Moments averaged exactly while 1/n > alpha (Voorhuis Sec. 6; Dundr's r = max(a, 1/age));
  /// off: EMA from the second frame on (Schied). [variant]
  bool momentsTrueAverage = false;
  /// History length cap.
  int maxHistoryLength = 255;
  /// Luminance used for moments, variance and w_l (Schied Rec.709; Dundr Rec.601; Gersthofer CIE L*). [variant]
  SvgfLuminance luminance = SvgfLuminance::rec709;

  // --- variance estimation (Schied Sec. 4.2) ---
  /// Below this history length (frames, including the current one) the variance is not
  /// temporal (Schied: "less than 4 frames").
  int shortHistoryFrames = 4;
  /// What replaces the temporal variance while the history is short. [variant]
  SvgfShortHistory shortHistory = SvgfShortHistory::spatialEstimate;
  /// Radius of the spatial estimate: 3 = 7x7 (Schied), 1 = 3x3 (Gersthofer Sec. 3.4.3). [variant]
  int spatialVarianceRadius = 3;
  /// Spatial estimate from the accumulated moments of the window (Voorhuis Sec. 6) instead of
  /// the current frame's luminance (Schied). [variant]
  bool spatialVarianceFromMoments = false;
  /// 3x3 Gaussian prefilter of the variance. [variant]
  SvgfVariancePrefilter variancePrefilter = SvgfVariancePrefilter::everyLevel;

  // --- edge-avoiding a-trous wavelet filter (Schied Sec. 4.3, Dammertz et al. 2010) ---
  SvgfKernel kernel = SvgfKernel::b3spline5x5;  ///< [variant]
  /// Number of a-trous levels (Schied 5; Dundr 5, "6 if smoother results are needed").
  int atrousIterations = 5;
  SvgfLevelOrder levelOrder = SvgfLevelOrder::fineToCoarse;  ///< [variant]
  /// 1-based executed level whose output becomes the colour history; 0 = none (Gersthofer). [variant]
  int feedbackLevel = 1;
  /// sigma_z of w_z = exp(-|z(p)-z(q)| / (sigma_z |grad z(p).(p-q)| + eps)) (Schied 1; Dundr 1; Voorhuis 1).
  float sigmaDepth = 1.0f;
  /// Exponent of w_n = max(0, n(p).n(q))^sigma_n, rounded to an integer (Schied 128; Dundr, Voorhuis 64). [variant]
  float sigmaNormal = 128.0f;
  /// sigma_l of w_l = exp(-|l(p)-l(q)| / (sigma_l sqrt(g3x3(Var)) + eps)) (Schied 4; Dundr 4; Voorhuis 5). [variant]
  float sigmaLuminance = 4.0f;
  /// eps of w_z = depthEpsilon + depthEpsilonRelative z(p) (not given by Schied; Dundr 0.005
  /// for normalized depth): the relative part keeps w_z independent of the scene's units; the
  /// absolute part (depth units) is the original form (0.01 with depthEpsilonRelative = 0).
  float depthEpsilon = 0.0f;
  float depthEpsilonRelative = 2.5e-3f;
  /// eps of w_l (Falcor-style 1e-10; Dundr "0.01 to 0.1" with the variance scale). [variant]
  float luminanceEpsilon = 1e-10f;
  /// Dundr Sec. 4.4.2: w_z = 1 where |grad z| > maxDepthSlope * z (very steep surfaces); 0 = off.
  float maxDepthSlope = 0.0f;
  SvgfLuminanceScale luminanceScale = SvgfLuminanceScale::standardDeviation;  ///< [variant]
  /// Propagate the variance through the levels, Var' = sum h^2 w^2 Var / (sum h w)^2 (Schied Eq. 4).
  bool varianceFiltering = true;
  /// Voorhuis Sec. 6: no per-level variance filtering for the indirect component. [variant]
  bool indirectVarianceFiltering = true;
  /// Voorhuis Eq. 8: sigma_l' = sigma_l (8 - min(7, h)), h = successful reprojections. [variant]
  bool shortHistoryBandwidth = false;
  /// Voorhuis Sec. 6: 3x3 median on diffuse pixels (roughness >= 0.9 or no roughness buffer),
  /// displayed frame only. [variant]
  bool fireflyMedian = false;

  // --- Voorhuis 2018: reflections (Sec. 4), per-material blend (Sec. 7) ---
  // Pixels are classed by the roughness of their primary hit (Buffer::Roughness): mirrors
  // (< pureSpecularRoughness), glossy with reflection motion (< reflectionRoughness), glossy
  // (< diffuseRoughness) and diffuse; see docs/methods/reflections.md.
  /// components = auto prefers the diffuse / specular lobes (Diffuse+Specular) over
  /// Direct+Indirect: the specular lobe alone follows the reflections. [variant]
  bool preferLobes = false;
  /// Motion of specular pixels: Base primary, NoSpecReproj none, Ours reflection (auto). [variant]
  SvgfSpecularMotion specularMotion = SvgfSpecularMotion::primary;
  /// Mirror pixels demodulated by primary x reflected albedo and edge-stopped on the
  /// reflected normal and virtual depth (Sec. 4.1). [variant]
  SvgfPart reflectedFeatures = SvgfPart::off;
  /// Eq. 6 spatial bandwidth from the reflected ray footprint for glossy pixels below
  /// reflectionRoughness (Sec. 4.2.2). [variant]
  SvgfPart glossyBandwidth = SvgfPart::off;
  /// omega of Eq. 6 (Voorhuis 0.5): world units, or with bandwidthPerLobe in widths of the
  /// pixel's reflected lobe at its hit.
  float bandwidthOmega = 0.5f;
  /// Eq. 6's omega is bandwidthOmega x the width of the pixel's reflected lobe where it lands,
  /// 2 alpha t (alpha = roughness^2, GGX; t = |reflectedPosition - position|), not a length in
  /// world units: the footprint is then compared with the blur of the reflection itself, so the
  /// bandwidth does not depend on the scene's unit or ignore the roughness. Off: the paper's
  /// world-unit omega. See docs/methods/reflections.md, "Eq. 6 in lobe widths".
  bool bandwidthPerLobe = true;
  /// Neighbourhood clipping of the history of non-diffuse pixels (Sec. 4.2.3). [variant]
  SvgfPart neighbourhoodClipping = SvgfPart::off;
  /// sigma of the separable 7x7 Gaussian prefilter of the clipping neighbourhood, pixels (not given).
  float clipSigma = 1.5f;
  /// Radius of the clipping window: 2 = 5x5 (Voorhuis).
  int clipWindowRadius = 2;
  /// The clipping prefilter and window take only pixels of the pixel's own surface (its class
  /// and, where the frame has it, its object id); off: every pixel in the window (the paper does
  /// not say). See docs/methods/reflections.md, "Neighbourhood clipping at silhouettes".
  bool clipOwnSurface = true;
  /// Blend floor alphaSpecular on specular pixels, alphaColor on diffuse ones (Sec. 7). [variant]
  SvgfPart materialAlpha = SvgfPart::off;
  /// Colour blend floor of specular pixels (Voorhuis 0.1).
  float alphaSpecular = 0.1f;
  /// TAA follows the reflection motion on glossy pixels below reflectionRoughness too, not only
  /// on mirrors (the paper does not say; off: their motion comes from the noisy sampled depth,
  /// and TAA shows each pixel's history unfiltered, see docs/methods/reflections.md).
  bool taaGlossyReflectionMotion = false;
  /// TAA's history on mirror pixels: at the reflection motion (default), at the primary motion
  /// (Base's), or none (TAA passes them through, as NoSpecReproj does on every specular pixel):
  /// sharper minified reflections, several times the still-camera flicker (the measured trade
  /// in docs/methods/reflections.md, "TAA on mirrors").
  SvgfTaaMirrorHistory taaMirrorHistory = SvgfTaaMirrorHistory::reflectionMotion;
  /// Roughness below which a (metallic) primary hit is a pure mirror (the renderer's 0.02).
  float pureSpecularRoughness = 0.02f;
  /// Roughness below which glossy pixels get reflection motion and Eq. 6 (Voorhuis 0.4, Beckmann).
  float reflectionRoughness = 0.4f;
  /// Roughness at and above which a hit is diffuse: no clipping, alphaColor, firefly median (Voorhuis 0.9).
  float diffuseRoughness = 0.9f;
  /// Algorithm 1's LDSP scaled by the step size 4-2-1 (Voorhuis); off: the plain LDSP.
  bool ldspScaling = true;
  /// Cap on the diamond search's LDSP iterations per pixel (not in the paper).
  int searchIterations = 64;
  /// Subpixel refinement of the reflection motion.
  bool subpixelMotion = true;
  /// How: Eqs. 2-3 (inverseDistance, the paper's) or quadratic (exact where the previous
  /// world positions are locally linear; docs/methods/reflections.md, "Subpixel fit").
  SvgfSubpixelFit subpixelFit = SvgfSubpixelFit::quadratic;

  /// Dundr Sec. 5, progressive rendering below 1 spp: where the frame has Buffer::SampleMask,
  /// unsampled pixels keep their history, pixels without any data weigh 0 in the filter and
  /// are filled by it, and the fed-back level replaces only this frame's sampled pixels.
  bool useSampleMask = true;

  // --- Gersthofer (VR stereo, Sec. 3.3-3.5); with components = composite ---
  /// Fixed blend weights: colour and moments mix alpha wherever reprojection succeeded (Sec.
  /// 3.4.1, "a fixed aggregation factor of alpha = 0.2"), instead of max(1/n, alpha). [variant]
  bool fixedAlpha = false;
  /// Eq. 3.1: with a sample mask, a sampled pixel whose reprojection failed is scaled by 1/c,
  /// c the coverage (sampled share of the visible pixels). In composite mode empty pixels
  /// without history are black samples of the filter (his masking, which the boost makes up
  /// for), not Dundr's holes. [variant]
  bool maskBoost = false;
  /// Coverage c of Eq. 3.1; 0 = measured per frame from Buffer::SampleMask.
  float maskCoverage = 0.0f;
  /// Sec. 3.4.2: 3x3 median (per channel) of the accumulated indirect diffuse, against caustic
  /// fireflies; off on frames with a sample mask of coverage < 1 ("disabled if masking is
  /// enabled"). [variant]
  bool indirectDiffuseMedian = false;
  /// Sec. 3.4.2: two-view denoising (rtd::StereoDenoiser) shares the accumulated indirect
  /// diffuse between the eyes: each eye's world positions are projected into the other eye,
  /// its validated bilinear taps blended in. Off: the eyes are denoised independently. [variant]
  bool eyeReprojection = false;
  /// Weight of the other eye's reprojected indirect diffuse (0.5: "double the sample count").
  float eyeBlend = 0.5f;
  /// Eq. 3.2 and w_r = 0.01 + sqrt(roughness) in every a-trous level (needs Roughness; w_zi
  /// also SecondaryDistance, the indirect ray length, accumulated like the colour). [variant]
  bool glossyWeights = false;
  /// "w_r is only active for glossy BRDFs": pixels with metalness >= this (all pixels where
  /// the frame has no Buffer::Metalness).
  float glossyMetalness = 0.5f;
  /// Sec. 3.4.3: the spatial variance estimate is also guided by the mesh id (neighbours with
  /// another ObjectId weigh 0). [variant]
  bool spatialVarianceObjectId = false;
  /// Sec. 3.5: FXAA (Lottes 2009) on the linear output, after remodulation (Gersthofer replaces
  /// TAA by it). [variant]
  bool fxaa = false;
  /// Sec. 3.5: tone map as the very last step (after FXAA); none keeps linear radiance.
  SvgfToneMap toneMap = SvgfToneMap::none;

  /// Emitter pixels left out of the a-trous levels and the spatial-variance window (issue 12;
  /// docs/methods/svgf.md, "Emitters"), here and in Gersthofer's pipeline. Off by default: on
  /// the renderer's Cornell box it costs 0.06 dB (the ceiling next to the lamp loses the taps
  /// on the lamp, on the bright side of its illumination), elsewhere it changes nothing.
  EmitterSettings emitters{.excludeEmitters = false};
  ReprojectionSettings reprojection;
  TaaSettings taa;

  /// Setting "variant" by name is a preset: it resets the [variant] fields to that paper's
  /// defaults (fields set afterwards override them). Called by every backend's set().
  void settingSet(std::string_view name) {
    if (isPreset(name)) applyVariant(variant);
  }
  /// The settings that are presets (SettingInfo::preset): "variant".
  static bool isPreset(std::string_view name) { return name == "variant"; }

  /// Resets the [variant] fields to the papers' defaults.
  void applyVariant(SvgfVariant v) {
    const SvgfSettings base;  // Schied et al. 2017
    variant = v;
    alphaColor = base.alphaColor;
    alphaMoments = base.alphaMoments;
    momentsTrueAverage = base.momentsTrueAverage;
    luminance = base.luminance;
    shortHistory = base.shortHistory;
    spatialVarianceRadius = base.spatialVarianceRadius;
    spatialVarianceFromMoments = base.spatialVarianceFromMoments;
    variancePrefilter = base.variancePrefilter;
    kernel = base.kernel;
    levelOrder = base.levelOrder;
    feedbackLevel = base.feedbackLevel;
    sigmaNormal = base.sigmaNormal;
    sigmaLuminance = base.sigmaLuminance;
    luminanceEpsilon = base.luminanceEpsilon;
    luminanceScale = base.luminanceScale;
    indirectVarianceFiltering = base.indirectVarianceFiltering;
    shortHistoryBandwidth = base.shortHistoryBandwidth;
    fireflyMedian = base.fireflyMedian;
    components = base.components;
    fixedAlpha = base.fixedAlpha;
    maskBoost = base.maskBoost;
    indirectDiffuseMedian = base.indirectDiffuseMedian;
    eyeReprojection = base.eyeReprojection;
    glossyWeights = base.glossyWeights;
    spatialVarianceObjectId = base.spatialVarianceObjectId;
    fxaa = base.fxaa;
    taa.taa = TaaSettings{}.taa;
    preferLobes = base.preferLobes;
    specularMotion = base.specularMotion;
    reflectedFeatures = base.reflectedFeatures;
    glossyBandwidth = base.glossyBandwidth;
    neighbourhoodClipping = base.neighbourhoodClipping;
    materialAlpha = base.materialAlpha;
    taa.taaAlpha = TaaSettings{}.taaAlpha;
    taa.taaHistoryFilter = TaaSettings{}.taaHistoryFilter;
    switch (v) {
      case SvgfVariant::schied: break;
      case SvgfVariant::dundr:  // Dundr, "Progressive SVGF", Sec. 4
        components = SvgfComponents::lobes;      // the tracer's diffuse (+ specular) light, else colour / albedo
        alphaColor = alphaMoments = 0.1f;        // "values around 0.1"
        momentsTrueAverage = true;               // r = max(a, 1/age) for light and moments
        luminance = SvgfLuminance::rec601;       // 0.299R + 0.587G + 0.114B
        shortHistory = SvgfShortHistory::disableLuminanceWeight;  // spatial estimate omitted
        variancePrefilter = SvgfVariancePrefilter::once;          // Sec. 4.3, stage 3
        kernel = SvgfKernel::binomial3x3;        // Fig. 4 kernel
        levelOrder = SvgfLevelOrder::firstThenCoarseToFine;
        sigmaNormal = 64.0f;
        luminanceEpsilon = 0.05f;                // "between 0.01 and 0.1"
        luminanceScale = SvgfLuminanceScale::variance;
        taa.taaAlpha = 0.1f;                     // "the same ratio r"
        // Sec. 4.5: the final frame is reprojected "the same way as we did in the reproject
        // phase" (bilinear), disocclusions ignored; with the subpixel alpha the Catmull-Rom
        // history scores within 0.03 dB of it (docs/methods/taa.md, "The history filter with
        // the subpixel alpha").
        taa.taaHistoryFilter = TaaHistoryFilter::bilinear;
        break;
      case SvgfVariant::gersthofer:  // Gersthofer, VR stereo, Sec. 3.3-3.5
        components = SvgfComponents::composite;  // one stream, indirect diffuse handled apart
        fixedAlpha = true;                       // "a fixed aggregation factor of alpha = 0.2"
        maskBoost = true;                        // Eq. 3.1
        indirectDiffuseMedian = true;            // firefly removal (off while masking)
        eyeReprojection = true;
        luminance = SvgfLuminance::cieLightness;
        feedbackLevel = 0;                       // "not fed back ... due to correlated sampling"
        spatialVarianceRadius = 1;               // 3x3 cross-bilateral
        spatialVarianceObjectId = true;          // "depth, normal and mesh ID"
        glossyWeights = true;                    // Eq. 3.2 and w_r
        fxaa = true;                             // FXAA instead of TAA (Sec. 3.5)
        taa.taa = false;
        break;
      case SvgfVariant::voorhuisRobustness:  // Voorhuis Sec. 6 only (with the Sec. 7 sigmas)
      case SvgfVariant::voorhuis:            // Voorhuis "Ours": Sec. 4, 6 and 7
        momentsTrueAverage = true;
        spatialVarianceFromMoments = true;
        sigmaNormal = 64.0f;
        sigmaLuminance = 5.0f;
        indirectVarianceFiltering = false;
        shortHistoryBandwidth = true;
        fireflyMedian = true;
        if (v == SvgfVariant::voorhuisRobustness) break;
        preferLobes = true;
        specularMotion = SvgfSpecularMotion::automatic;
        reflectedFeatures = glossyBandwidth = neighbourhoodClipping = materialAlpha = SvgfPart::automatic;
        break;
      case SvgfVariant::voorhuisNoSpecReproj:  // Sec. 7.1: Base without history and TAA on specular pixels
        specularMotion = SvgfSpecularMotion::none;
        [[fallthrough]];
      case SvgfVariant::voorhuisBase:  // Sec. 7: the author's SVGF with sigma_n 64, sigma_l 5
        sigmaNormal = 64.0f;
        sigmaLuminance = 5.0f;
        break;
    }
  }
  static SvgfSettings forVariant(SvgfVariant v) {
    SvgfSettings s;
    s.applyVariant(v);
    return s;
  }

  template <class V> void visit(V& v) {
    v("variant", variant,
      "preset of the [variant] settings (applied before the other settings): schied, dundr, gersthofer; voorhuis = Voorhuis' whole method "
      "(Ours), voorhuisBase / voorhuisNoSpecReproj = its baselines, voorhuisRobustness = its Sec. 6 changes only",
      {"schied", "dundr", "gersthofer", "voorhuis", "voorhuisBase", "voorhuisNoSpecReproj", "voorhuisRobustness"});
    v("components", components, "[variant] radiance streams filtered separately and summed; composite (Gersthofer): "
      "indirectDiffuse and the rest of color accumulated apart, added, filtered as one; diffuse: the diffuse "
      "lobe filtered, the specular one added unfiltered (color where the frame lacks them); lobes: diffuseSpecular where the "
      "frame has the lobes, color where it does not",
      {"auto", "color", "directIndirect", "diffuseSpecular", "composite", "diffuse", "lobes"});
    v("alphaColor", alphaColor, "[variant] colour blend floor w = max(1/n, alpha) (Schied 0.2, Dundr 0.1)", Range{0.001, 1});
    v("alphaMoments", alphaMoments, "[variant] moments blend (Schied 0.2, Dundr 0.1)", Range{0.001, 1});
    v("momentsTrueAverage", momentsTrueAverage, "[variant] moments averaged exactly for short histories (Voorhuis, Dundr)");
    v("maxHistoryLength", maxHistoryLength, "history length cap", Range{1, 65535});
    v("luminance", luminance, "[variant] luminance of moments/variance/w_l (Schied rec709, Dundr rec601, Gersthofer CIE L*)",
      {"rec709", "rec601", "cieLightness"});
    v("shortHistoryFrames", shortHistoryFrames, "history length below which the variance is not temporal (Schied 4)", Range{0, 65535});
    v("shortHistory", shortHistory, "[variant] variance for short histories (Schied spatial, Dundr weight off)",
      {"spatialEstimate", "disableLuminanceWeight", "temporal"});
    v("spatialVarianceRadius", spatialVarianceRadius, "[variant] spatial variance window radius (Schied 3 = 7x7, Gersthofer 1 = 3x3)", Range{1, 7});
    v("spatialVarianceFromMoments", spatialVarianceFromMoments, "[variant] spatial variance from accumulated moments (Voorhuis)");
    v("variancePrefilter", variancePrefilter, "[variant] 3x3 Gaussian of the variance: every level (Schied), once (Dundr), off",
      {"everyLevel", "once", "off"});
    v("kernel", kernel, "[variant] a-trous kernel (Schied 5x5 B3 spline, Dundr 3x3 binomial)", {"5x5", "3x3"});
    v("atrousIterations", atrousIterations, "a-trous levels (Schied 5)", Range{0, 8});
    v("levelOrder", levelOrder, "[variant] step order: 1,2,4,.. (Schied); 1 then ..,4,2 (Dundr); coarse to fine",
      {"fineToCoarse", "firstThenCoarseToFine", "coarseToFine"});
    v("feedbackLevel", feedbackLevel, "[variant] executed level fed back as colour history, 0 = none (Schied 1, Gersthofer 0)", Range{0, 8});
    v("sigmaDepth", sigmaDepth, "sigma_z of the depth weight (Schied 1)", Range{0, 1e9});
    v("sigmaNormal", sigmaNormal, "[variant] normal weight exponent (Schied 128, Dundr/Voorhuis 64)", Range{0, 4096});
    v("sigmaLuminance", sigmaLuminance, "[variant] sigma_l of the luminance weight (Schied 4, Voorhuis 5)", Range{0, 1e9});
    v("depthEpsilon", depthEpsilon, "absolute part of the depth weight's eps, depth units (before issue 12: 0.01)", Range{0, 1e9});
    v("depthEpsilonRelative", depthEpsilonRelative,
      "scale-free part of the depth weight's eps, times the pixel's depth (0.0025: 0.01 at depth 4)", Range{0, 1e9});
    v("luminanceEpsilon", luminanceEpsilon, "[variant] eps of the luminance weight (Dundr 0.05)", Range{1e-12, 1e9});
    v("maxDepthSlope", maxDepthSlope, "depth weight off where |grad z| > maxDepthSlope * z (Dundr); 0 = off", Range{0, 1e9});
    v("luminanceScale", luminanceScale, "[variant] w_l scaled by std deviation (Schied) or variance (Dundr)",
      {"standardDeviation", "variance"});
    v("varianceFiltering", varianceFiltering, "propagate variance through the levels (Schied Eq. 4)");
    v("indirectVarianceFiltering", indirectVarianceFiltering, "[variant] per-level variance filtering for the indirect component (Voorhuis: off)");
    v("shortHistoryBandwidth", shortHistoryBandwidth, "[variant] sigma_l * (8 - min(7, h)) (Voorhuis Eq. 8)");
    v("fireflyMedian", fireflyMedian, "[variant] 3x3 median on diffuse pixels, display only (Voorhuis)");
    v("preferLobes", preferLobes, "[variant] components=auto prefers diffuse+specular over direct+indirect (Voorhuis)");
    v("specularMotion", specularMotion,
      "[variant] motion of specular pixels: primary (Base), none (NoSpecReproj, no TAA either), reflection (diamond "
      "search, Voorhuis Sec. 4; needs the reflection buffers), auto (reflection where possible)",
      {"primary", "none", "reflection", "auto"});
    v("reflectedFeatures", reflectedFeatures,
      "[variant] mirrors demodulated by primary x reflected albedo, edge-stopped on reflected features (Voorhuis Sec. 4.1)",
      {"off", "on", "auto"});
    v("glossyBandwidth", glossyBandwidth, "[variant] Eq. 6 spatial bandwidth from the reflected footprint, glossy < reflectionRoughness",
      {"off", "on", "auto"});
    v("bandwidthOmega", bandwidthOmega,
      "omega of Eq. 6 (Voorhuis 0.5): in widths of the reflected lobe at its hit (bandwidthPerLobe), else world units",
      Range{1e-6, 1e9});
    v("bandwidthPerLobe", bandwidthPerLobe,
      "Eq. 6's omega = bandwidthOmega x the reflected lobe's width at its hit, 2 roughness^2 |reflectedPosition - "
      "position|; false: world units (the paper)");
    v("neighbourhoodClipping", neighbourhoodClipping, "[variant] clip the history of non-diffuse pixels (Voorhuis Sec. 4.2.3)",
      {"off", "on", "auto"});
    v("clipSigma", clipSigma, "sigma of the 7x7 Gaussian prefilter of the clipping neighbourhood, pixels", Range{0.1, 100});
    v("clipWindowRadius", clipWindowRadius, "clipping window radius (Voorhuis 2 = 5x5)", Range{0, 7});
    v("clipOwnSurface", clipOwnSurface,
      "clipping neighbourhood of a pixel = the pixels of its own surface (class and object id) in the window; off: all");
    v("materialAlpha", materialAlpha, "[variant] blend floor alphaSpecular on specular, alphaColor on diffuse pixels (Voorhuis)",
      {"off", "on", "auto"});
    v("alphaSpecular", alphaSpecular, "colour blend floor of specular pixels (Voorhuis 0.1)", Range{0.001, 1});
    v("taaGlossyReflectionMotion", taaGlossyReflectionMotion,
      "TAA follows the reflection motion on glossy pixels below reflectionRoughness too (off: on mirrors only)");
    v("taaMirrorHistory", taaMirrorHistory,
      "TAA history on mirror pixels: reflectionMotion, primaryMotion or none (sharper curved mirrors, more flicker)",
      {"reflectionMotion", "primaryMotion", "none"});
    v("pureSpecularRoughness", pureSpecularRoughness, "roughness below which a hit is a mirror (renderer 0.02)", Range{0, 1});
    v("reflectionRoughness", reflectionRoughness, "roughness below which glossy pixels get reflection motion (Voorhuis 0.4)", Range{0, 1});
    v("diffuseRoughness", diffuseRoughness, "roughness from which a hit is diffuse (Voorhuis 0.9)", Range{0, 1.01});
    v("ldspScaling", ldspScaling, "diamond search LDSP scaled 4-2-1 (Voorhuis); off: plain LDSP");
    v("searchIterations", searchIterations, "cap on diamond-search iterations per pixel", Range{1, 4096});
    v("subpixelMotion", subpixelMotion, "subpixel refinement of reflection motion");
    v("subpixelFit", subpixelFit,
      "subpixel refinement: inverseDistance (Voorhuis Eqs. 2-3) or quadratic (minimum of the quadratic through the 3x3's "
      "squared distances, exact for locally linear world positions)",
      {"inverseDistance", "quadratic"});
    v("useSampleMask", useSampleMask, "progressive sub-1-spp mode when the frame has sampleMask (Dundr Sec. 5)");
    v("fixedAlpha", fixedAlpha, "[variant] blend exactly alphaColor/alphaMoments where reprojection succeeded (Gersthofer 3.4.1)");
    v("maskBoost", maskBoost, "[variant] sampleMask: sampled pixels without history scaled by 1/c, empty ones black (Gersthofer Eq. 3.1)");
    v("maskCoverage", maskCoverage, "coverage c of Eq. 3.1; 0 = measured from the frame's sampleMask", Range{0, 1});
    v("indirectDiffuseMedian", indirectDiffuseMedian, "[variant] 3x3 median of accumulated indirect diffuse, off while masking (Gersthofer 3.4.2)");
    v("eyeReprojection", eyeReprojection, "[variant] stereo: share accumulated indirect diffuse between the eyes (Gersthofer 3.4.2)");
    v("eyeBlend", eyeBlend, "weight of the other eye's reprojected indirect diffuse (0.5: double the samples)", Range{0, 1});
    v("glossyWeights", glossyWeights, "[variant] a-trous weights w_zi (Eq. 3.2) and w_r = 0.01 + sqrt(roughness) (Gersthofer 3.4.3)");
    v("glossyMetalness", glossyMetalness, "w_r applies where metalness >= this (\"glossy BRDFs\")", Range{0, 1});
    v("spatialVarianceObjectId", spatialVarianceObjectId, "[variant] spatial variance also guided by object id (Gersthofer 3.4.3)");
    v("fxaa", fxaa, "[variant] FXAA (Lottes 2009) on the linear output (Gersthofer 3.5)");
    v("toneMap", toneMap, "last step: none (linear radiance) or aces (Narkowicz fit, display-referred)", {"none", "aces"});
    emitters.visit(v);
    reprojection.visit(v);
    taa.visit(v);
  }
};

}  // namespace rtd
