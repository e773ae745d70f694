// rtdenoise — settings of the shared final temporal anti-aliasing pass (Karis 2014), which
// SVGF, A-SVGF and BMFR apply to their remodulated output.
#pragma once
#include "rtd/settings_visit.h"

namespace rtd {

/// Values the TAA clamps and blends. display: each channel tone-mapped by Reinhard x/(1+x)
/// and gamma-encoded (square root) first and decoded after, as Dundr (Sec. 4.5), Voorhuis
/// (Sec. 3.0) and the BMFR code (gamma-encoded LDR) anti-alias display-referred colour, so a
/// few bright pixels do not dominate the YCoCg box and the blend; the output stays linear HDR.
/// linear: the radiance itself (rtdenoise before 2026-12).
enum class TaaDomain { linear, display };
/// Clamp bounds: the 3x3 box (Karis 2014, Dundr), or the mean of the 3x3 box's and the 5-tap
/// cross's bounds (BMFR code).
enum class TaaNeighbourhood { box3x3, boxCross };
/// How the previous output is resampled at the reprojected position. bilinear: the 2x2
/// footprint (Karis 2014's hardware fetch); it low-passes the history once per frame, which
/// under sub-pixel motion compounds into blur (docs/methods/taa.md). catmullRom: the separable
/// 4x4 Catmull-Rom cubic (Keys 1981, a = -1/2), exact for quadratics; Jimenez's SMAA T2x
/// evaluates the same filter with 9 (or, corners dropped, 5) bilinear fetches, here its 16
/// texels are read directly. Its overshoot is contained by the neighbourhood clamp; taps off
/// the frame repeat the border texel; a pixel whose reprojection rejected one of its 2x2 taps
/// (disocclusion, edge) takes the bilinear history. catmullRom is the default since 2026-12-03
/// (docs/methods/taa.md, "The history filter as the default"). With the subpixel alpha
/// (taaSubpixelAlpha, since that night) the two filters score within 0.03 dB for the SVGF
/// family, Catmull-Rom keeping a slight SSIM edge under camera motion (<= 0.0016), and BMFR's
/// constant alpha still gains 0.2 dB from it on corridorglossy; bilinear costs ~2/3 of the
/// pass's time on avx2. The `dundr` preset uses bilinear, his Sec. 4.5's fetch
/// (docs/methods/taa.md, "The history filter with the subpixel alpha").
enum class TaaHistoryFilter { bilinear, catmullRom };

struct TaaSettings {
  /// Run TAA on the output.
  bool taa = true;
  /// Weight of the current frame in the TAA blend (Karis 2014: ~0.1; BMFR code: 0.2).
  float taaAlpha = 0.1f;
  /// Rise of the current frame's weight with the history fetch's subpixel offset: at a pixel
  /// whose history is fetched at fractional offsets (fx, fy) from a texel centre the blend
  /// weight is min(1, taaAlpha + taaSubpixelAlpha (fx (1 - fx) + fy (1 - fy))). fx (1 - fx) is
  /// the variance (in px^2) of the bilinear tap weights, the blur each resampling adds to the
  /// history; frames without jitter give TAA nothing to resolve, so under sub-pixel motion that
  /// blur compounds over the ~1/taaAlpha frames the history holds (docs/methods/taa.md, "Subpixel
  /// alpha"). 0: Karis's constant alpha. A still camera and whole-pixel motion keep taaAlpha.
  float taaSubpixelAlpha = 2.0f;
  TaaDomain taaDomain = TaaDomain::display;
  TaaNeighbourhood taaNeighbourhood = TaaNeighbourhood::box3x3;
  TaaHistoryFilter taaHistoryFilter = TaaHistoryFilter::catmullRom;
  /// The clamp box of a pixel takes only the neighbours on its own surface: those whose
  /// surface key (passes/taa_keys.h: object id, the Voorhuis surface class where the method
  /// classifies, and an emitter bit where the method leaves emitters out of its filter) equals
  /// the pixel's; the pixel itself always counts. At a silhouette (a reflective orb's rim in
  /// front of a darker wall) or next to a lamp whose filtered radiance is 0, the plain 3x3 box
  /// also spans the other surface, so history carried over from it is not clamped away
  /// (issues 12 and 13; docs/methods/taa.md, "Own-surface clamp box"). A frame without the
  /// buffers the keys need (ObjectId, Emission) is clamped as with the option off. On by
  /// default since 2026-12-03: measured on every method and scene, it gains up to +3.5 dB on
  /// moving renderer scenes (pillars), +1.4 to +1.6 dB on the Cornell box, and lowers the
  /// temporal error; what it costs (+1-2 % temporal error on the Blender glossy fixture and on
  /// still Voorhuis sequences, ~25 % more time in the TAA pass) is listed in
  /// docs/methods/taa.md, "The defaults".
  bool taaOwnSurface = true;
  /// No TAA history where the method's reprojection found none: a pixel none of whose history
  /// taps passed the reprojection's consistency tests (a disocclusion: SVGF's depth, normal and
  /// object-id tests, BMFR's position test) keeps the current frame, as a pixel whose history
  /// lies off the frame does. Karis's TAA takes the history at any reprojected position and
  /// leaves ghosts to the clamp, which keeps them where the 3x3 box holds both surfaces (along
  /// the silhouettes a moving camera uncovers; docs/methods/taa.md, "History rejection").
  /// Off by default (on from 2026-12-03 to the same day's Catmull-Rom default): it gains 0.1 to
  /// 0.2 dB on the pillars' camera move and little elsewhere, but on the Blender lamp fixture
  /// (Cycles frames, a moving cube) the fresh noisy pixels it leaves at the cube's
  /// disocclusions raise the temporal error of svgf and Dundr 2 % above rtdenoise's before
  /// issue 12 and cost BMFR 0.2 dB (docs/methods/taa.md, "The history filter as the default").
  bool taaHistoryRejection = false;

  template <class V> void visit(V& v) {
    v("taa", taa, "final TAA with YCoCg 3x3 neighbourhood clamping (Karis 2014)");
    v("taaAlpha", taaAlpha, "weight of the current frame in the TAA blend (Karis 2014: 0.1, BMFR: 0.2)", Range{0.001, 1});
    v("taaSubpixelAlpha", taaSubpixelAlpha,
      "rise of the blend weight with the history fetch's subpixel offset: alpha + k (fx(1-fx) + fy(1-fy)), at most 1; "
      "0 = constant alpha",
      Range{0, 8});
    v("taaDomain", taaDomain,
      "values TAA clamps and blends: display = Reinhard x/(1+x) + gamma 2 per channel, inverted after (Dundr, Voorhuis, BMFR "
      "code); linear = HDR radiance",
      {"linear", "display"});
    v("taaNeighbourhood", taaNeighbourhood, "clamp bounds: 3x3 box (Karis, Dundr) or mean of box and 5-tap cross (BMFR code)",
      {"box3x3", "boxCross"});
    v("taaHistoryFilter", taaHistoryFilter,
      "resampling of the reprojected history: bilinear (2x2) or catmullRom (4x4 Catmull-Rom cubic, Jimenez's SMAA T2x; "
      "less blur under sub-pixel motion, overshoot clamped to the neighbourhood)",
      {"bilinear", "catmullRom"});
    v("taaOwnSurface", taaOwnSurface,
      "clamp box over the pixel's own surface only (neighbours with its object id, surface class and emitter bit; "
      "issues 12/13): off = the plain 3x3 box");
    v("taaHistoryRejection", taaHistoryRejection,
      "no TAA history where the reprojection's consistency tests rejected every history tap (disocclusions): the current "
      "frame there");
  }
};

}  // namespace rtd
