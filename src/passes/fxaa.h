// Shared pass: fast approximate anti-aliasing (Lottes 2009, "FXAA", the "quality" variant) and
// the final tone map, Gersthofer's post-processing (Sec. 3.5): FXAA on the linear HDR image,
// then ACES (Narkowicz fit, passes/tonemap.h) as the very last step. GLSL twin:
// src/backend/vulkan/shaders/fxaa.comp.
//
// Per pixel: the luma contrast of the 4-neighbourhood decides whether the pixel is on an edge
// (range >= max(edgeThresholdMin, edgeThreshold * brightest)); the 3x3 second differences
// decide whether the edge is horizontal or vertical and the steeper neighbour the side; a walk
// along the edge in both directions (steps 1,1,1,1,1,1.5,2,2,2,2,4,8 pixels) finds its ends,
// where the luma leaves the edge's mean by a quarter of the gradient; the pixel then samples
// the image bilinearly, shifted towards the edge by the offset of its position along the edge
// (0.5 at an end, 0 in the middle), or by the sub-pixel blend of the 3x3 low-pass where that is
// larger. The luma of HDR radiance is sqrt(Y / (1 + Y)) (Reinhard-compressed, gamma 2), the
// perceptual luma FXAA's thresholds are meant for.
#pragma once
#include "core/plane.h"

namespace rtd {

struct FxaaParams {
  float edgeThreshold = 0.166f;      ///< minimum local contrast, relative to the brightest (Lottes: 0.166)
  float edgeThresholdMin = 0.0833f;  ///< minimum contrast in dark regions (Lottes: 0.0833)
  float subpixel = 0.75f;            ///< amount of sub-pixel aliasing removal (Lottes: 0.75)
};

/// FXAA's luma of linear HDR radiance: sqrt(Y / (1 + Y)), Y the Rec.709 luminance.
float fxaaLuma(float r, float g, float b);

/// FXAA of `in` into `out` (different planes), clamped to the edge at the image border;
/// `luma` (the image's size) receives fxaaLuma of `in`.
void fxaa(const Plane3& in, const FxaaParams& p, Plane& luma, Plane3& out);

/// ACES (Narkowicz) per channel, in place: the display-referred [0, 1] image.
void toneMapAces(Plane3& rgb);

}  // namespace rtd
