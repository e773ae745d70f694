// Supersampling with guide rays (Voorhuis 2018, Sec. 5) on the Vulkan backend: the GPU twin of
// GuideRays::premix / resolve (src/passes/guide_rays.cpp), recorded around a Vulkan denoiser in
// its own submission (GuideRays::denoise, include/rtd/guide_rays.h).
#pragma once
#include <array>

#include "backend/vulkan/context.h"
#include "rtd/guide_rays.h"

namespace rtd::detail {

/// What GuideRays keeps on the device between frames (reallocated when a frame needs more).
struct GuideRaysGpu {
  /// Uploads the guide frame and the samples (checked by the caller), records the passes
  /// guideRays.upload (staging copies), guideRays.premix (guide_assign, then guide_premix per
  /// radiance buffer), the method, guideRays.resolve (guide_resolve and the read-back copy) in
  /// `denoiser`'s submission, and returns the resolved image.
  Image denoise(Denoiser& denoiser, const Frame& guides, const GuideRaySamples& samples,
                const GuideRaySettings& settings);

 private:
  vk::Context* ctx_ = nullptr;
  vk::DeviceBuffer staging_, readback_;
  std::array<vk::DeviceBuffer, kBufferCount> guide_;    ///< the guide frame's buffers, interleaved
  std::array<vk::DeviceBuffer, kBufferCount> samples_;  ///< sample k's radiance at k * w * h pixels
  std::array<vk::DeviceBuffer, kBufferCount> mixed_;    ///< Eq. 7 of each radiance buffer
  vk::DeviceBuffer sampleDepth_, sampleNormal_, offsets_, assigned_, filtered_, resolved_;
};

}  // namespace rtd::detail
