// The Vulkan twin of svgf::Filter (svgf_filter.h): variance estimate, a-trous levels and
// feedback of one radiance stream, recorded as compute dispatches. Shared by `svgf` and `asvgf`.
#pragma once
#include <string>

#include "backend/vulkan/passes.h"
#include "methods/svgf/svgf_filter.h"

namespace rtd::svgf {

/// FilterExtras on the GPU: every pointer may be null.
struct GpuFilterExtras {
  /// Level-0 source in the accumulator's layout (R, G, B, m1, m2, length) when the colour is
  /// not the accumulated one (Gersthofer's composite); null: accumulator.current().
  const vk::Planes* source = nullptr;
  const vk::Planes* objectId = nullptr;  ///< mesh-id term of the spatial variance
  const vk::Planes* indirectDistance = nullptr;  ///< glossy weights (GpuAtrousLevel's fields)
  const vk::Planes* indirectDistanceScale = nullptr;
  const vk::Planes* centreScale = nullptr;
  /// Voorhuis Eq. 6 (the GPU form of FilterParams::spatialFalloff).
  const vk::Planes* spatialFalloff = nullptr;
  /// FilterParams::surfaceKey on the GPU (also the spatial variance's key where objectId is null).
  const vk::Planes* surfaceKey = nullptr;
};

class GpuFilter {
 public:
  void resize(vk::Context& ctx, int w, int h);
  uint64_t bytes() const;

  /// Filter::run on the GPU: level 0 from `accumulator` (planes R, G, B, m1, m2, length) and
  /// `current` (demodulated sample), p.iterations levels over the guide (`depth`, `normal`,
  /// `gradient`), feedback of level p.feedbackLevel into the accumulator's colour (with `mask`:
  /// at sampled pixels only). Passes "variance" + suffix and "atrous<i>" + suffix. Returns the
  /// planes holding the result (R, G, B, luminance, variance).
  const vk::Planes& run(vk::Recorder& rec, const vk::Planes& depth, const vk::Planes& normal,
                        const vk::Planes& gradient, vk::GpuTemporalAccumulator& accumulator, const vk::Planes& current,
                        const vk::Planes* mask, const FilterParams& p, const std::string& suffix = {},
                        const GpuFilterExtras& extras = {});

 private:
  vk::Planes levels_[2], sigmaScale_;
  vk::Planes prefilteredVariance_;  // variancePrefilter = once
  vk::Planes valid_[2];  // a-trous validity per level in the progressive mode
};

}  // namespace rtd::svgf
