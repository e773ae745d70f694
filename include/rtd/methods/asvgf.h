// rtdenoise — method "asvgf": adaptive spatiotemporal variance-guided filtering (Schied et al.
// 2018, "Gradient estimation for real-time adaptive temporal filtering", as restated and
// simplified in Higginson's thesis Sec. 2.3 and 3.3). SVGF whose temporal accumulation drops
// history where the shading changed, measured by re-shading last frame's samples with their
// old random seeds (the renderer's gradient samples, Buffer::GradientSample/Previous/Current).
// docs/methods/asvgf.md describes the pipeline, every default's source and every choice.
#pragma once
#include "rtd/methods/reprojection.h"
#include "rtd/methods/taa.h"

namespace rtd {

/// Where the temporal gradient comes from.
enum class AsvgfGradientSource {
  /// A-SVGF: the frame's gradient samples (Buffer::GradientSample, GradientPrevious,
  /// GradientCurrent), one re-shaded sample per 3x3 stratum. A frame without them is an error.
  samples,
  /// NOT A-SVGF: for inputs that cannot re-shade (Blender, most engines), an anti-lag estimate
  /// in the spirit of NRD ReLAX: the current frame's mean luminance against the reprojected
  /// history's, both averaged per 3x3 stratum and then over each surface by the gradient's
  /// a-trous levels, less the noise expected of that average. It needs no extra buffers; it
  /// detects only changes larger than the noise of the average, so it is slower and blurrier
  /// than re-shading.
  historyAntilag,
};

struct AsvgfSettings {
  static constexpr const char* kMethod = "asvgf";

  // --- temporal gradient (Schied 2018 Sec. 4; Higginson Sec. 2.3.1, "Gradient Estimation") ---
  AsvgfGradientSource gradientSource = AsvgfGradientSource::samples;
  /// A-trous levels over the 1/3-resolution gradient (3x3 kernel, steps 1, 2, 4, ...; depth and
  /// normal edge-stopping on each stratum's features). Thesis: not given; Schied 2018's code: 5.
  int gradientIterations = 5;
  /// G' = clamp(scale * G, 0, 1) before the history is shortened (Q2RTX flt_antilag_hf = 1;
  /// the thesis omits the factor, i.e. 1).
  float antilagScale = 1.0f;
  /// historyAntilag only: differences below this many standard deviations of the filtered
  /// current mean count as noise (our choice; see docs/methods/asvgf.md).
  float antilagNoiseSigmas = 3.0f;

  // --- adaptive temporal accumulation (Higginson Sec. 2.3.1, "Temporal Accumulation") ---
  /// Cap of N' = min(N (1 - G)^e + 1, cap) (thesis and Q2RTX: 256).
  int maxHistoryLength = 256;
  /// Exponent e of the history shrink (1 - G)^e (thesis and Q2RTX: 10).
  float historyExponent = 10.0f;
  /// alpha = mix(max(1/N', minAlpha), 1, G) for the colour; the thesis's formula has no floor
  /// (omitted "hyper-parameters"): Q2RTX flt_min_alpha_color_hf = 0.1.
  float minAlphaColor = 0.1f;
  /// The same for the luminance moments (Q2RTX flt_min_alpha_moments_hf = 0.01).
  float minAlphaMoments = 0.01f;

  // --- variance and a-trous filter, shared with svgf (thesis Eq. 2.8-2.12; values Schied 2017) ---
  /// History length below which the variance is the 7x7 spatial estimate (Schied 2017: 4).
  int shortHistoryFrames = 4;
  /// Radius of that spatial window (Schied 2017: 3 = 7x7).
  int spatialVarianceRadius = 3;
  /// A-trous levels of the colour (5x5 B3 spline, steps 1, 2, 4, ...; thesis: tested several,
  /// headline count not given; Schied 2017/2018: 5).
  int atrousIterations = 5;
  /// 1-based level whose output becomes the colour history; 0 = none (Schied 2017/2018: 1).
  int feedbackLevel = 1;
  /// sigma_z of w_d (Eq. 2.9; thesis: not given; Schied 2017: 1).
  float sigmaDepth = 1.0f;
  /// Exponent sigma_n of w_n (Eq. 2.8; thesis: not given; Schied 2017: 128).
  float sigmaNormal = 128.0f;
  /// sigma_l of w_l (Eq. 2.10; thesis: not given; Schied 2017: 4).
  float sigmaLuminance = 4.0f;
  /// eps of w_d = depthEpsilon + depthEpsilonRelative z(p) (as svgf).
  float depthEpsilon = 0.0f;
  float depthEpsilonRelative = 2.5e-3f;
  /// eps of w_l (as svgf).
  float luminanceEpsilon = 1e-10f;
  /// Thesis Sec. 1.2.1 / Fig. 3.6: the filter's normal is the normal of the reflected hit where
  /// the frame has Buffer::ReflectedNormal (mirror pixels), keeping reflected edges sharp.
  bool reflectedNormals = true;

  ReprojectionSettings reprojection;
  TaaSettings taa;

  template <class V> void visit(V& v) {
    v("gradientSource", gradientSource,
      "samples: A-SVGF from the frame's gradient samples; historyAntilag: NOT A-SVGF, a ReLAX-style estimate "
      "from the current frame against reprojected history, for inputs without gradient samples",
      {"samples", "historyAntilag"});
    v("gradientIterations", gradientIterations, "a-trous levels of the 1/3-res gradient (Schied 2018 code: 5)", Range{0, 8});
    v("antilagScale", antilagScale, "G' = clamp(scale G, 0, 1) (Q2RTX flt_antilag_hf 1)", Range{0, 1e9});
    v("antilagNoiseSigmas", antilagNoiseSigmas, "historyAntilag: differences below k std devs of the filtered mean are noise",
      Range{0, 1e9});
    v("maxHistoryLength", maxHistoryLength, "cap of N' = min(N (1-G)^e + 1, cap) (thesis 256)", Range{1, 65535});
    v("historyExponent", historyExponent, "e of the history shrink (1-G)^e (thesis 10)", Range{0, 1e9});
    v("minAlphaColor", minAlphaColor, "alpha = mix(max(1/N', min), 1, G) for colour (thesis none; Q2RTX 0.1)", Range{0, 1});
    v("minAlphaMoments", minAlphaMoments, "the same for the moments (thesis none; Q2RTX 0.01)", Range{0, 1});
    v("shortHistoryFrames", shortHistoryFrames, "history length below which the variance is spatial (Schied 4)",
      Range{0, 65535});
    v("spatialVarianceRadius", spatialVarianceRadius, "spatial variance window radius (Schied 3 = 7x7)", Range{1, 7});
    v("atrousIterations", atrousIterations, "a-trous levels of the colour (Schied 5)", Range{0, 8});
    v("feedbackLevel", feedbackLevel, "level fed back as colour history, 0 = none (Schied 1)", Range{0, 8});
    v("sigmaDepth", sigmaDepth, "sigma_z of the depth weight (Schied 1)", Range{0, 1e9});
    v("sigmaNormal", sigmaNormal, "normal weight exponent (Schied 128)", Range{0, 4096});
    v("sigmaLuminance", sigmaLuminance, "sigma_l of the luminance weight (Schied 4)", Range{0, 1e9});
    v("depthEpsilon", depthEpsilon, "absolute part of the depth weight's eps, depth units (as svgf)", Range{0, 1e9});
    v("depthEpsilonRelative", depthEpsilonRelative, "scale-free part of the depth weight's eps, times the pixel's depth (as svgf)",
      Range{0, 1e9});
    v("luminanceEpsilon", luminanceEpsilon, "eps of the luminance weight", Range{1e-12, 1e9});
    v("reflectedNormals", reflectedNormals, "filter with the reflected hit's normal on mirror pixels (thesis Fig. 3.6)");
    reprojection.visit(v);
    taa.visit(v);
  }
};

}  // namespace rtd
