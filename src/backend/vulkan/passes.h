// The shared passes on the GPU (twins of src/passes/): demodulation, reprojection, temporal
// accumulation and TAA, recorded through a vk::Recorder. Every method's Vulkan implementation
// reuses these, as the CPU methods reuse src/passes/.
#pragma once
#include <array>

#include "backend/vulkan/context.h"
#include "rtd/frame.h"
#include "rtd/methods/reprojection.h"

namespace rtd::vk {

/// One frame on the GPU: each imported buffer as planes (allocated on first use, kept), which
/// of them this frame has, and its camera (32 floats: worldToCamera then projection).
struct GpuFrame {
  int width = 0, height = 0;
  std::array<Planes, kBufferCount> planes;
  std::array<bool, kBufferCount> present{};
  DeviceBuffer camera;
  Camera cameraValue;

  bool has(Buffer b) const { return present[int(b)]; }
  const Planes& operator[](Buffer b) const { return planes[int(b)]; }
  /// The planes of `b`, or the context's dummy buffer where the frame lacks it.
  Binding bindingOf(Buffer b, const Context& ctx) const;
};

/// out = radiance / albedo' (albedo may be null: a copy).
void demodulate(Recorder& rec, const Planes& color, const Planes* albedo, Planes& out);
/// out = illumination * albedo' (first three planes of `illumination`).
void remodulate(Recorder& rec, const Planes& illumination, const Planes* albedo, Planes& out);

/// Reprojection records (8 planes, see shaders/reprojection.glsl) for `cur`; with no previous
/// frame every pixel is None.
void reproject(Recorder& rec, const GpuFrame& cur, const GpuFrame* prev, const ReprojectionSettings& s, Planes& rp);

/// Colour, luminance moments and history length, double-buffered (6 planes each: R, G, B,
/// moment 1, moment 2, length), like TemporalAccumulator.
class GpuTemporalAccumulator {
 public:
  void resize(Context& ctx, int w, int h);
  void reset() {}  // a reprojection without previous frame marks every pixel None: history is never read
  void run(Recorder& rec, const Planes& rp, const Planes& color, float alpha, float momentsAlpha, int maxHistoryLength);
  /// This frame's result; methods that feed a filtered colour back (SVGF) write its planes 0-2.
  Planes& current() { return history_[cur_]; }
  const Planes& current() const { return history_[cur_]; }

 private:
  Planes history_[2];
  int cur_ = 0;
};

/// Karis TAA on the remodulated output; its result is the next frame's history.
class GpuTaa {
 public:
  void resize(Context& ctx, int w, int h);
  void reset() { valid_ = false; }
  const Planes& run(Recorder& rec, const Planes& rp, const Planes& color, float alpha);

 private:
  Planes history_[2];
  int cur_ = 0;
  bool valid_ = false;
};

}  // namespace rtd::vk
