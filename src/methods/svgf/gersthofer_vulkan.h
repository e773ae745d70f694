// The Vulkan twin of GersthoferEye (gersthofer.h): Gersthofer's pipeline for one eye, recorded
// as compute dispatches in two halves around the exchange between the eyes.
#pragma once
#include <vector>

#include "backend/vulkan/passes.h"
#include "methods/svgf/svgf_filter_vulkan.h"
#include "rtd/denoiser.h"
#include "rtd/methods/svgf.h"

namespace rtd::svgf {

class GpuGersthoferEye {
 public:
  void resize(vk::Context& ctx, int w, int h);
  void reset();
  /// GersthoferEye::front: reprojection, guide, demodulation, boost, accumulation, median.
  void front(vk::Recorder& rec, const vk::GpuFrame& frame, const vk::GpuFrame* previous, const SvgfSettings& s);
  /// The accumulated (median-filtered) indirect diffuse (3 planes).
  const vk::Planes& indirectDiffuse() const { return *indirectDiffuse_; }
  /// The composite accumulator (R, G, B, m1, m2, length): the exchange's source validity.
  const vk::Planes& history() const { return composite_.current(); }
  /// Where the exchange writes; once called, back() composites it.
  vk::Planes& shared();
  /// GersthoferEye::back: composite, filter, remodulation, TAA / FXAA / tone map.
  const vk::Planes& back(vk::Recorder& rec, const vk::GpuFrame& frame, const SvgfSettings& s, bool& emissionIncluded);
  std::vector<MemoryUse> memory() const;

 private:
  int width_ = 0, height_ = 0;
  vk::Planes reprojection_, gradient_, guideNormal_, counter_, boost_;
  vk::Planes currentComposite_, currentIndirect_;
  vk::GpuTemporalAccumulator composite_, indirect_;
  vk::Planes distance_[2], glossyCentre_, glossyScale_;
  int distanceCur_ = 0;
  bool distanceValid_ = false;
  vk::Planes median_, shared_, source_, output_, post_, fxaa_;
  const vk::Planes* indirectDiffuse_ = &median_;
  bool masked_ = false, exchanged_ = false, boosted_ = false;
  GpuFilter filter_;
  vk::GpuTaa taa_;
};

}  // namespace rtd::svgf
