// An analytic test scene: a pinhole camera translating over a checkered floor, a back wall and
// a sphere, ray-cast in closed form. It gives exact feature buffers, exact motion, a noise-free
// reference and 1-spp-like noisy radiance (radiance times an exponential variate of mean 1),
// with no renderer involved. Used by tests, benchmarks and `rtdenoise bench`.
#pragma once
#include <array>
#include <cstdint>

#include "rtd/sequence.h"

namespace rtd::synthetic {

struct Scene {
  int width = 160;
  int height = 90;
  float cameraSpeed = 0.02f;     ///< camera translation along +x per frame (world units)
  float verticalFov = 1.0472f;   ///< radians (60 degrees)
  float noise = 1.0f;            ///< 0: noise-free; 1: exponential noise of mean 1
  uint32_t seed = 1;
  /// The sun is off from this frame index on (a light switch); -1: always on.
  int sunOffFrame = -1;
  /// Write A-SVGF's gradient samples (docs/sequence-format.md): per 3x3 stratum the previous
  /// frame's brightest sample, forward-projected to this frame's camera and re-shaded with its
  /// noise variate (the synthetic "seed"), as `rtdenoise render` does.
  bool gradientSamples = true;
  /// Camera rotation about the world's y axis per frame (radians), and a jittered camera: frame
  /// i's sample of pixel (x, y) is at (x + 0.5, y + 0.5) + jitterOf(i) (Halton 2, 3 offsets in
  /// [-0.5, 0.5)), motion staying the unjittered (native) motion. For the engine-convention
  /// tests; the gradient samples do not follow them (turn gradientSamples off with either).
  float cameraYawSpeed = 0.0f;
  bool jitter = false;
};

/// Sub-pixel jitter of frame `index` (pixels, y down); zero unless scene.jitter.
std::array<float, 2> jitterOf(const Scene& scene, int index);

/// Frame `index` (0-based; its number is index + 1). Buffers: color, albedo, normal, depth,
/// position, motion, objectId, roughness and, with gradientSamples, gradientSample,
/// gradientPrevious, gradientCurrent (all 0 in frame 0); camera matrices valid. `reference`, if
/// not null, receives the noise-free radiance (RGB).
Frame makeFrame(const Scene& scene, int index, Image* reference = nullptr);

}  // namespace rtd::synthetic
