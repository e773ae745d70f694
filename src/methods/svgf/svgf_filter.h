// The spatial half of SVGF for one radiance stream (Schied et al. 2017 Sec. 4.2-4.3): the
// variance estimate, the a-trous levels and the feedback of one level into the colour history.
// Shared by the methods that accumulate first and then filter like SVGF (`svgf`, `asvgf`):
// each turns its settings into FilterParams and calls Filter::run once per stream per frame.
// The Vulkan twin is GpuFilter (svgf_filter_vulkan.h).
#pragma once
#include <string>

#include "core/timer.h"
#include "methods/svgf/svgf_passes.h"
#include "passes/atrous.h"
#include "passes/temporal_accumulation.h"
#include "rtd/methods/svgf.h"

namespace rtd::svgf {

/// What the filter does with one stream. svgf builds it with filterParams(); other methods fill
/// it from their own settings (the fields mean what the SvgfSettings fields of the same names
/// mean, docs/methods/svgf.md).
struct FilterParams {
  /// Short-history estimate, window, depth/normal weights (also those of the a-trous levels)
  /// and the luminance of moments, variance and w_l.
  VarianceParams variance;
  SvgfVariancePrefilter variancePrefilter = SvgfVariancePrefilter::everyLevel;
  /// Per-pixel multiplier of sigma_l (luminanceSigmaScale): Dundr's w_l off for short
  /// histories (variance.shortHistory == disableLuminanceWeight) and Voorhuis Eq. 8.
  bool shortHistoryBandwidth = false;
  SvgfKernel kernel = SvgfKernel::b3spline5x5;
  int iterations = 5;
  SvgfLevelOrder levelOrder = SvgfLevelOrder::fineToCoarse;
  /// 1-based executed level whose output overwrites the accumulated colour; 0 = none.
  int feedbackLevel = 1;
  float sigmaLuminance = 4.0f;
  float luminanceEpsilon = 1e-10f;
  SvgfLuminanceScale luminanceScale = SvgfLuminanceScale::standardDeviation;
  /// Var' = sum h^2 w^2 Var / (sum h w)^2 between levels (Schied Eq. 4).
  bool propagateVariance = true;
  /// Voorhuis Eq. 6: per-pixel narrowing of the kernel (AtrousLevel::spatialFalloff), or null.
  const PaddedPlane* spatialFalloff = nullptr;
  /// Voorhuis Sec. 4.1, the reflected guide's mirror pixels apart (AtrousLevel::surfaceKey;
  /// also the spatial variance's key where FilterExtras::objectId is null), or null.
  const PaddedPlane* surfaceKey = nullptr;

  /// Border the planes need: the widest tap offset, the spatial window, one SIMD vector.
  int requiredPad() const;
};

/// SVGF's parameters for a stream (`indirect`: Voorhuis' indirectVarianceFiltering applies).
FilterParams filterParams(const SvgfSettings& s, bool indirect);

/// Per-pixel multiplier of sigma_l from the history length: 0 where w_l is off (Dundr, n <
/// shortHistoryFrames with disableLuminanceWeight), Voorhuis Eq. 8 where enabled, else 1.
void luminanceSigmaScale(const Plane& historyLength, const FilterParams& p, PaddedPlane& out);
/// Whether that multiplier can be other than 1 (else the levels run without its plane).
bool usesSigmaScale(const FilterParams& p);

/// What a run takes beyond the accumulation: Gersthofer's pipeline (gersthofer.h) and SVGF's
/// fused variance rows; every pointer may be null.
struct FilterExtras {
  /// Filter::varianceRows already ran on every row for this run (as the accumulation's
  /// afterRows) and counted this many short-history pixels: the variance pass then adds only
  /// the spatial estimate. Null: the whole pass. Not with `input`.
  const size_t* varianceRowsShortCount = nullptr;
  /// The level-0 colour when it is not the accumulated colour (his composite of the separately
  /// accumulated components); null: accumulator.color().
  const Plane3* input = nullptr;
  /// Object ids for the mesh-id term of the spatial variance (VarianceInputs::objectId).
  const PaddedPlane* objectId = nullptr;
  /// The glossy weights w_zi and w_r of every level (AtrousLevel's fields of the same names).
  const PaddedPlane* indirectDistance = nullptr;
  const PaddedPlane* indirectDistanceScale = nullptr;
  const PaddedPlane* centreScale = nullptr;
  /// The stream is the method's whole output: the result goes into these planes, remodulated
  /// by `remodulateAlbedo` (null: as it is), instead of the returned image. The last level
  /// writes it (AtrousLevel's fields of the same names) where it can: a level that is neither
  /// fed back nor has the reflected stream's terms; otherwise a pass after it does.
  Plane3* remodulatedOut = nullptr;
  const std::vector<Plane>* remodulateAlbedo = nullptr;
};

/// The filter's planes, allocated once per size (resize) and reused by every stream.
class Filter {
 public:
  void resize(int w, int h, int pad);
  int pad() const { return pad_; }
  /// Filters one stream: the level-0 image from `accumulator` (colour, moments, length) and
  /// `current` (this frame's demodulated sample, for the spatial variance estimate), then
  /// p.iterations a-trous levels over `guide`. After executed level p.feedbackLevel its output
  /// replaces accumulator.color() (with `mask`, Dundr Sec. 5: only at pixels sampled this
  /// frame; missing pixels weigh 0 in the levels). Times the passes "variance" + suffix and
  /// "atrous<i>" + suffix (with extras.remodulatedOut the last "atrous<n>+remodulate", or
  /// "remodulate" after it) into `stats`. Returns the filtered image (its colour planes hold
  /// the accumulation when p.iterations is 0; not the result with extras.remodulatedOut);
  /// valid until the next run.
  const AtrousImage& run(const AtrousGuide& guide, TemporalAccumulator& accumulator, const Plane3& current,
                         const Plane* mask, const FilterParams& p, FrameStats& stats, const std::string& suffix = {},
                         const FilterExtras& extras = {});
  /// The variance pass's rows [rowBegin, rowEnd) (svgf::varianceRows) from `accumulator`'s
  /// current results and `current`, from any thread; returns their short-history pixels. Run as
  /// the accumulation's AccumulationOptions::afterRows, they read the rows while those are in
  /// cache (~0.4 ms of a 1280x720 frame at two threads); the run() that follows (the same
  /// accumulator, current and p.variance) takes the count's sum in
  /// FilterExtras::varianceRowsShortCount.
  size_t varianceRows(const TemporalAccumulator& accumulator, const Plane3& current, const FilterParams& p, int rowBegin,
                      int rowEnd);

  /// Every plane the filter keeps (CPU denoisers' PlaneInspection).
  void forEachPlane(const PlaneVisitor& visit) const {
    for (const auto& im : levels_) im.forEachPlane(visit);
    prefilteredVariance_.visit(visit, "prefiltered variance");
    sigmaScale_.visit(visit, "sigma scale");
    for (const auto& v : valid_) v.visit(visit, "valid");
    for (const auto& v : scratch_) v.visit(visit, "variance window input");
  }

 private:
  AtrousImage levels_[2];  ///< the levels' input and output, in turn
  PaddedPlane prefilteredVariance_;  ///< variancePrefilter = once
  PaddedPlane sigmaScale_;  ///< usesSigmaScale
  PaddedPlane valid_[2];  ///< with a sample mask
  PaddedPlane scratch_[2];  ///< the spatial variance's windowed moments
  int pad_ = 0;
};

}  // namespace rtd::svgf
