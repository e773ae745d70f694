// Shared pass: albedo demodulation and remodulation (Schied et al. 2017 Sec. 4: filter
// untextured illumination so texture detail is not blurred).
#pragma once
#include "core/frame_data.h"

namespace rtd {

/// Albedo channels below this are treated as 1 (not divided, not multiplied), so black and
/// emissive surfaces keep their radiance and nothing is divided by zero.
constexpr float kAlbedoEpsilon = 1e-3f;

inline float demodulationFactor(float albedo) { return albedo > kAlbedoEpsilon ? albedo : 1.0f; }

/// out = radiance / albedo' per channel. With no albedo, a copy.
void demodulate(const std::vector<Plane>& radiance, const std::vector<Plane>* albedo, Plane3& out);
/// out = illumination * albedo' per channel (in place). With no albedo, nothing.
void remodulate(Plane3& illumination, const std::vector<Plane>* albedo);
/// out[x] = in[x] * albedo'[x] for n values (a copy with no albedo); out may be in.
void remodulateSpan(const float* in, const float* albedo, float* out, int n);
/// Row y of out = illumination * albedo' (a copy with no albedo); out may be illumination.
void remodulateRow(const Plane3& illumination, const std::vector<Plane>* albedo, Plane3& out, int y);

}  // namespace rtd
