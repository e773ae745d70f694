// rtdenoise — supersampling with guide rays (Voorhuis 2018, Sec. 5; after Bauszat et al. 2011),
// around any denoiser. A pixel's first sample goes through its centre (the "guide ray": the
// frame the denoiser sees, with its noise-free features); its other samples are jittered. Each
// non-guide sample is assigned to the most similar of the four guide rays around it (depth and
// normal), and mixed into that guide's radiance before filtering (Eq. 7); after filtering it
// takes that guide's filtered colour, and each pixel is the average of its samples (an
// anti-aliased image without TAA). docs/methods/reflections.md, "Supersampling".
#pragma once
#include <memory>
#include <vector>

#include "rtd/denoiser.h"
#include "rtd/sequence.h"

namespace rtd {

/// The non-guide samples of one frame: sample k (k = 1 .. spp-1) of every pixel.
struct GuideRaySamples {
  /// Per sample index: its radiance buffers (Color and the same ones of Direct, Indirect,
  /// Diffuse, Specular, Emission, IndirectDiffuse as the guide frame) and its primary hit's
  /// Depth and Normal (sky: depth >= the guides' sky depth, normal 0), in the native conventions.
  std::vector<Frame> samples;
  /// Per sample index: XY, the sample's position minus its pixel's centre, in pixels, in
  /// [-0.5, 0.5] (x right, y down the rows).
  std::vector<Image> offsets;
};

/// What decides which guide a sample joins: the smallest
///   |z_s - z_g| / max(z_s, z_g) + normalWeight (1 - n_s . n_g)
/// over the (up to) four guide rays whose centres surround the sample; guides outside the image
/// are not candidates (the sample's own pixel always is one).
struct GuideRaySettings {
  float normalWeight = 1.0f;
};

namespace detail { struct GuideRaysGpu; }

class GuideRays {
 public:
  GuideRays();
  ~GuideRays();
  GuideRays(GuideRays&&) noexcept;
  GuideRays& operator=(GuideRays&&) noexcept;

  /// Assigns every non-guide sample to a guide and returns `guides` with each radiance buffer
  /// replaced by Eq. 7, (u(p) + sum_{q in A(p)} u(q)) / (1 + |A(p)|); the other buffers are
  /// copied. Throws rtd::Error when a sample lacks Color, Depth or Normal, its radiance buffers
  /// differ from the guides', or a buffer's size differs from the guides'.
  Frame premix(const Frame& guides, const GuideRaySamples& samples, const GuideRaySettings& settings = {});
  /// After filtering: `filtered` is the denoiser's RGB output for the pre-mixed guides; returns
  /// per pixel the average of its guide's filtered colour and, for each non-guide sample, the
  /// filtered colour of the guide it joined. premix() must have run on this frame's samples.
  Image resolve(const Image& filtered) const;

  /// premix(), `denoiser` on the pre-mixed frame, resolve(): the whole of Sec. 5 around one
  /// frame, on the denoiser's backend. On Vulkan the assignment, Eq. 7 and the copy back run as
  /// compute passes (shaders guide_assign, guide_premix, guide_resolve) in the denoiser's own
  /// submission: the guide frame and the samples are uploaded once, only the resolved image is
  /// read back, and the denoiser's stats() hold the passes "guideRays.upload",
  /// "guideRays.premix" and "guideRays.resolve" (GPU time). On the CPU the wall times of the
  /// pre-mix and the copy back are in passes() instead.
  /// Checks the samples as premix() does. Buffers GPU memory for the next frame's call.
  Image denoise(Denoiser& denoiser, const Frame& guides, const GuideRaySamples& samples,
                const GuideRaySettings& settings = {});
  /// The pre-mix and copy-back times of the last denoise() that ran outside the denoiser's
  /// stats() (the CPU; empty after a Vulkan one).
  const std::vector<PassTiming>& passes() const { return passes_; }

  /// After premix() or a CPU denoise() (not a Vulkan one, which keeps them on the GPU):
  /// index (y * width + x) of the guide sample k (1-based) of pixel `pixel` joined.
  int assignedGuide(int k, int pixel) const { return assign_[size_t(k - 1)][size_t(pixel)]; }
  /// 1 + |A(p)| per guide pixel: how many samples its pre-mixed radiance averages.
  const std::vector<int>& mixCount() const { return count_; }

 private:
  int width_ = 0, height_ = 0;
  std::vector<std::vector<int>> assign_;
  std::vector<int> count_;
  std::vector<PassTiming> passes_;
  std::unique_ptr<detail::GuideRaysGpu> gpu_;  // Vulkan buffers, kept between frames
};

}  // namespace rtd
