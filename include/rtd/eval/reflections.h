// rtdenoise evaluation of reflections (Voorhuis 2018, Sec. 7): the accuracy of the reflection
// motion vectors against the brute-force search (Sec. 7.4, Figs. 12-13), and metrics restricted
// to reflective pixels. docs/evaluation.md ("Reflections") describes them.
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "rtd/image.h"
#include "rtd/methods/svgf.h"
#include "rtd/sequence.h"

namespace rtd::eval {

struct ReflectionMotionSettings {
  bool ldspScaling = true;      ///< Algorithm 1's 4-2-1 scaled LDSP (Voorhuis); off: plain LDSP
  int searchIterations = 64;    ///< as SvgfSettings::searchIterations
  bool subpixel = true;         ///< subpixel refinement, for both searches
  /// The refinement, for both searches: as SvgfSettings::subpixelFit.
  SvgfSubpixelFit subpixelFit = SvgfSubpixelFit::quadratic;
  int bruteForceRadius = 100;   ///< the reference's window: (2 radius)^2 = the paper's 200 x 200
  /// The reference's glossy distance: to r_far's half-line (the text's "ray", the default: over
  /// the window the whole line also matches points behind the far surface, which no reflection
  /// sees), or false: Eq. 5 as written, to its line, as the search (docs/methods/reflections.md).
  bool referenceOnRay = true;
  bool mirrors = true, glossy = true;
  float pureSpecularRoughness = 0.02f, reflectionRoughness = 0.4f, diffuseRoughness = 0.9f;
};

/// One frame's reflection motion vectors against the brute-force reference.
struct ReflectionMotionFrame {
  int number = 0;
  uint64_t pixels = 0;         ///< mirror and glossy pixels whose brute-force search found a match
  uint64_t missed = 0;         ///< ... of which the diamond search found none (no history there)
  double meanError = 0;        ///< mean |MV_search - MV_bruteforce| in pixels over the others (NaN without)
  double withinOnePixel = 0;   ///< share of `pixels` with an error <= 1 px (a missed pixel is not)
  double meanTaps = 0;         ///< distance evaluations per pixel of the diamond search
};

/// For every frame after the first of a sequence with the renderer's reflection buffers
/// (roughness, reflectedPosition, mirrorDirection, secondaryDistance): the diamond search of
/// each mirror / glossy pixel (classes and distances as SVGF's Voorhuis mode) compared with the
/// brute-force search over the window, both with the same subpixel refinement. Throws
/// rtd::Error naming the missing buffer. `progress(done, total)` after each frame.
std::vector<ReflectionMotionFrame> reflectionMotionError(const SequenceReader& sequence,
                                                         const ReflectionMotionSettings& settings = {},
                                                         const std::function<void(int, int)>& progress = {});

/// 1 where the pixel's primary hit has roughness below `roughness` (reflective; 0.4: the pixels
/// whose reflections the Voorhuis mode reprojects), else 0; one channel. Needs Buffer::Roughness.
Image reflectiveMask(const Frame& frame, float roughness = 0.4f);

/// PSNR (dB, peak 1) over the pixels where `mask` > 0.5, all channels; tone-mapped sRGB inputs.
double maskedPsnr(const Image& test, const Image& reference, const Image& mask);
/// Mean of the SSIM map (ssim()'s `map`) over the pixels where `mask` > 0.5.
double maskedSsim(const Image& test, const Image& reference, const Image& mask);

}  // namespace rtd::eval
