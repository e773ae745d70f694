// Gersthofer's pipeline (2020, "Spatio-Temporal Filtering for Real-Time Path Tracing in VR",
// Sec. 3.3-3.5), SVGF's `composite` mode, for one eye: its own history, run in two halves so
// that a two-view denoiser can exchange indirect diffuse light between the eyes in between.
//
//   front: reprojection, guide, demodulation, temporal accumulation of the composite (colour,
//          CIE L* moments, length) and of the indirect diffuse, the indirect ray length, the
//          3x3 median of the indirect diffuse (off while masking), which sampled pixels lack
//          history (the 1/c boost of Eq. 3.1);
//   [exchange: eyeReprojection() of each eye's indirect diffuse into the other, Sec. 3.4.2]
//   back:  composite = (direct + indirect specular) + indirect diffuse, boosted by 1/c where
//          Eq. 3.1 says (this frame's filter input only, not the history), variance (temporal, or
//          the 3x3 spatial estimate with the mesh-id term), five a-trous levels with the glossy
//          weights w_zi and w_r, remodulation, FXAA, tone map.
//
// The history holds the composite and the indirect diffuse (the thesis keeps "direct" and
// "indirect" textures; the difference of ours is his first one), both written from the
// temporal accumulation: neither the median, the other eye's light nor a filtered level goes
// back into it (feedbackLevel 0). docs/methods/stereo.md has the choices.
#pragma once
#include <vector>

#include "core/frame_data.h"
#include "methods/svgf/svgf_filter.h"
#include "passes/eye_reprojection.h"
#include "passes/reprojection.h"
#include "passes/taa.h"
#include "passes/temporal_accumulation.h"
#include "rtd/denoiser.h"
#include "rtd/methods/svgf.h"

namespace rtd::svgf {

/// Eq. 3.1: `factor` = 1/c where `mask` is 1 and the pixel has no history (reprojection
/// failed, or its taps hold no data: the gathered previous `historyLength` rounds to 0), 1
/// elsewhere. Returns the number of boosted pixels.
size_t boostDisoccluded(const Reprojection& rp, const Plane& previousHistoryLength, const Plane& mask, float coverage,
                        Plane& factor);

/// The two halves of the pipeline for one eye.
class GersthoferEye {
 public:
  /// Everything up to the exchange. Allocates (and resets) on a new size.
  void front(const FrameData& frame, const FrameData* previous, const SvgfSettings& s, FrameStats& stats);
  /// The eye's accumulated (median-filtered) indirect diffuse: what the other eye gathers.
  const Plane3& indirectDiffuse() const { return *indirectDiffuse_; }
  /// Where the exchange writes this eye's indirect diffuse with the other eye's blended in;
  /// once called, back() composites it instead of indirectDiffuse().
  Plane3& shared();
  /// Where the other eye may read this eye's light: sampled or accumulated pixels (history
  /// length > 0).
  const Plane& historyLength() const { return composite_.historyLength(); }
  /// Composite, filter and post-processing; returns the output (emission included when
  /// `emissionIncluded`, needed before a tone map).
  const Plane3& back(const FrameData& frame, const SvgfSettings& s, FrameStats& stats, bool& emissionIncluded);

  void reset();
  /// History and intermediate bytes (Table 5.4), without the frames.
  std::vector<MemoryUse> memory() const;
  /// Every float array it keeps (PlaneInspection): the history, then the per-frame planes.
  void forEachPlane(const PlaneVisitor& visit) const {
    visitHistory(visit);
    visitIntermediate(visit);
  }

 private:
  void resize(int w, int h, int pad);
  void visitHistory(const PlaneVisitor& visit) const;
  void visitIntermediate(const PlaneVisitor& visit) const;
  void accumulateDistance(const FrameData& frame, const Plane* mask, const SvgfSettings& s);

  int width_ = 0, height_ = 0;
  Reprojection reprojection_;
  AtrousGuide guide_;
  PaddedPlane objectId_, indirectDistance_, indirectDistanceScale_, centreScale_;
  Plane3 currentComposite_, currentIndirect_;  // this frame's demodulated samples
  TemporalAccumulator composite_, indirect_;   // history: composite (with moments) and indirect diffuse
  Plane distance_[2];                          // history: accumulated indirect ray length
  int distanceCur_ = 0;
  bool distanceValid_ = false;                 // distance_[distanceCur_] holds last frame's z_i
  Plane3 median_, shared_, input_;             // median, after the exchange, the filter's input
  Plane boost_;                                // Eq. 3.1's factor per pixel (1 or 1/c)
  bool boosted_ = false;                       // some pixel of this frame is boosted
  const Plane3* indirectDiffuse_ = &median_;
  bool masked_ = false;                        // this frame's sample mask leaves pixels out
  bool exchanged_ = false;                     // shared_ holds this frame's exchanged light
  Filter filter_;
  Plane3 output_, post_;
  Plane luma_;
  Taa taa_;
};

/// Eye reprojection in both directions (Sec. 3.4.2): each eye's shared() becomes its indirect
/// diffuse with the other eye's, gathered at its world positions, blended in (s.eyeBlend);
/// the validation follows s.reprojection. Returns the number of pixels that took light from
/// the other eye, per eye.
std::array<size_t, 2> exchangeIndirectDiffuse(GersthoferEye& left, const FrameData& leftFrame, GersthoferEye& right,
                                              const FrameData& rightFrame, const SvgfSettings& s);

}  // namespace rtd::svgf
