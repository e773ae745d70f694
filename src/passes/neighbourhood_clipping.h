// Shared pass: neighbourhood clipping tailored to SVGF (Voorhuis 2018, Sec. 4.2.3). The
// history of a non-diffuse pixel is clipped to the range of the current frame's colours in a
// 5x5 window before the temporal blend, as TAA does (Karis 2014), but the window is read from
// a separable 7x7 Gaussian of the current (noisy, demodulated) frame so that neighbouring
// pixels see coherent ranges. This pass builds the per-pixel box; the shared temporal
// accumulation applies it (AccumulationOptions::clipLow/clipHigh). GLSL twin:
// src/backend/vulkan/shaders/clip_box.comp.
#pragma once
#include <cstdint>

#include "core/plane.h"

namespace rtd {

struct ClipBoxOptions {
  int gaussianRadius = 3;  ///< 7x7 prefilter (Voorhuis)
  float sigma = 1.5f;      ///< of the prefilter, pixels (not given by the paper)
  int windowRadius = 2;    ///< 5x5 window (Voorhuis)
};

/// Per channel, low/high = min/max over the (2 windowRadius + 1)^2 window of G * current, G the
/// separable (2 gaussianRadius + 1)^2 Gaussian (weights normalized; both clamp to the image
/// edge). Where `clip` is given and 0 (diffuse pixels), low = -inf and high = +inf: the
/// history passes unclipped. `scratch` holds the prefiltered image (any size; resized).
void clipBox(const Plane3& current, const PixelVector<uint8_t>* clip, const ClipBoxOptions& opt, Plane3& low,
             Plane3& high, Plane3& scratch);

/// The normalized 1D weights of the prefilter (2 radius + 1 of them), shared with the GPU pass.
void clipGaussianWeights(int radius, float sigma, float* out);

}  // namespace rtd
