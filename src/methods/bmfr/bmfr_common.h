// What the CPU (bmfr.cpp) and Vulkan (bmfr_vulkan.cpp) implementations of BMFR share on the
// host side: the feature list of a frame, the regularization noise amplitude and the integer
// hash behind the noise and the sub-sampled rows (the shaders carry a GLSL twin of the hash,
// shaders/bmfr.glsl, that must stay bit-identical).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "rtd/frame.h"
#include "rtd/methods/bmfr.h"

namespace rtd::bmfr {

/// Where a feature column comes from. Positions enter the squares centred on the block
/// (w - c)^2, which spans the same space as {1, w, w^2} but keeps float precision when the
/// scene is far from the origin.
enum class FeatureKind : uint8_t { Constant, Normal, Position, PositionSquared, MaterialId, Roughness };

struct Feature {
  FeatureKind kind;
  int channel;
};

/// The frame's feature columns in fit order: the constant 1, then n, w, (w - c)^2 (three
/// channels each), material id and roughness, each when enabled and the frame has its buffer.
template <class Has> void selectFeatures(const BmfrSettings& s, Has&& has, std::vector<Feature>& features) {
  features.clear();
  features.push_back({FeatureKind::Constant, 0});
  auto add = [&](bool on, Buffer b, FeatureKind kind, int channels) {
    if (!on || !has(b)) return;
    for (int c = 0; c < channels; ++c) features.push_back({kind, c});
  };
  add(s.featureNormal, Buffer::Normal, FeatureKind::Normal, 3);
  add(s.featurePosition, Buffer::Position, FeatureKind::Position, 3);
  add(s.featurePositionSquared, Buffer::Position, FeatureKind::PositionSquared, 3);
  add(s.featureMaterialId, Buffer::MaterialId, FeatureKind::MaterialId, 1);
  add(s.featureRoughness, Buffer::Roughness, FeatureKind::Roughness, 1);
}

/// A feature whose half range over a block is at most this fraction of its magnitude is
/// constant to rounding and becomes a zero column (CPU normalization() and its GLSL twin in
/// shaders/bmfr_fit.comp). The magnitude of a channel of n or w is the largest |value| of the
/// vector's three channels on the block; (w - c)^2 is constant when w is.
inline constexpr float kConstantFeature = 1e-6f;

/// Buffers BMFR cannot run without: colour, and the normal / position while their features are on.
inline std::vector<Buffer> requiredBuffers(const BmfrSettings& s) {
  std::vector<Buffer> b{Buffer::Color};
  if (s.featureNormal) b.push_back(Buffer::Normal);
  if (s.featurePosition || s.featurePositionSquared) b.push_back(Buffer::Position);
  return b;
}

/// Optional feature buffers, read only while their features are on.
inline std::vector<Buffer> optionalBuffers(const BmfrSettings& s) {
  std::vector<Buffer> b;
  if (s.featureMaterialId) b.push_back(Buffer::MaterialId);
  if (s.featureRoughness) b.push_back(Buffer::Roughness);
  if (s.taa.taaOwnSurface) b.push_back(Buffer::ObjectId);  // the own-surface box's keys (passes/taa_keys.h)
  return b;
}

/// Integer hash (a PCG output permutation) to a uniform float in [0, 1).
inline float hashUniform(uint32_t a, uint32_t b, uint32_t c) {
  uint32_t h = a * 747796405u + b * 2891336453u + c * 3266489917u + 0x9e3779b9u;
  h = ((h >> ((h >> 28u) + 4u)) ^ h) * 277803737u;
  h = (h >> 22u) ^ h;
  return float(h >> 8) * (1.0f / 16777216.0f);
}

/// Least-squares rows of a block of side `size`: every pixel, or `samplesPerBlock` of them.
inline int rowsPerBlock(int size, int samplesPerBlock) {
  const int all = size * size;
  return samplesPerBlock > 0 ? std::min(samplesPerBlock, all) : all;
}

/// Amplitude of the uniform noise on [-eps, eps]: the regularization's strength is the noise
/// column's energy rows * eps^2 / 3, which the paper tuned for 32x32 = 1024 rows, so fits with
/// fewer rows (sub-sampled blocks) scale eps by sqrt(1024 / rows) (docs/methods/bmfr.md).
inline float noiseAmplitude(float noiseAmount, int rows) {
  return noiseAmount * std::sqrt(std::max(1.0f, 1024.0f / float(rows)));
}

}  // namespace rtd::bmfr
