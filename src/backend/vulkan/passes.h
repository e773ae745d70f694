// The shared passes on the GPU (twins of src/passes/): demodulation, reprojection, temporal
// accumulation and TAA, recorded through a vk::Recorder. Every method's Vulkan implementation
// reuses these, as the CPU methods reuse src/passes/.
#pragma once
#include <array>

#include "backend/vulkan/context.h"
#include "rtd/frame.h"
#include "rtd/methods/emitters.h"
#include "rtd/methods/reprojection.h"
#include "rtd/methods/taa.h"

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
  /// `moments` false: 4 planes each (R, G, B, length; BMFR), as TemporalAccumulator::resize(w,
  /// h, false); runAdaptive() then throws.
  void resize(Context& ctx, int w, int h, bool moments = true);
  /// The plane of current() that holds the history length.
  int lengthPlane() const { return moments_ ? 5 : 3; }
  /// Zeroes the history (lengths 0) before the next run, as TemporalAccumulator::reset does:
  /// needed when the reprojection still has a previous frame (a stream switched buffers).
  void reset() { clear_ = true; }
  /// luminanceMode: MomentLuminance (0 Rec709, 1 Rec601, 2 CIE L*); cumulativeMoments: moments
  /// weighted max(1/n, momentsAlpha) like the colour, else a plain EMA (AccumulationOptions).
  /// sampleMask (Buffer::SampleMask, AccumulationOptions::sampleMask): where it is 0 the
  /// history carries over unchanged (shader variant temporal_accumulation_masked).
  /// alphaPlane (AccumulationOptions::alphaPlane): per-pixel colour blend floor; clipBox (6
  /// planes: low RGB, high RGB; AccumulationOptions::clipLow/clipHigh): the colour history is
  /// clamped to it before the blend (Voorhuis). cumulativeColor false: fixed weights alpha /
  /// momentsAlpha wherever there is history (AccumulationOptions::cumulativeColor).
  void run(Recorder& rec, const Planes& rp, const Planes& color, float alpha, float momentsAlpha, int maxHistoryLength,
           uint32_t luminanceMode = 0, bool cumulativeMoments = true, const Planes* sampleMask = nullptr,
           const Planes* alphaPlane = nullptr, const Planes* clipBox = nullptr, bool cumulativeColor = true);
  /// A-SVGF's adaptive accumulation (AccumulationOptions::temporalGradient; shader variant
  /// temporal_accumulation_gradient): G in the first plane of `gradient`, one texel per
  /// stride x stride pixels; alpha and momentsAlpha are the weights' floors.
  void runAdaptive(Recorder& rec, const Planes& rp, const Planes& color, float alpha, float momentsAlpha,
                   int maxHistoryLength, uint32_t luminanceMode, const Planes& gradient, int stride,
                   float historyExponent);
  /// Bytes of the history (both buffers).
  uint64_t bytes() const { return uint64_t(history_[0].buffer.size() + history_[1].buffer.size()); }
  /// This frame's result; methods that feed a filtered colour back (SVGF) write its planes 0-2.
  Planes& current() { return history_[cur_]; }
  const Planes& current() const { return history_[cur_]; }

 private:
  /// Swaps the history buffers (clearing the previous one after reset()); returns it.
  const Planes& advance(Recorder& rec);
  Planes history_[2];
  int cur_ = 0;
  bool clear_ = false;
  bool moments_ = true;
};

/// Parameters of one a-trous level (twin of AtrousLevel, src/passes/atrous.h).
struct GpuAtrousLevel {
  int radius = 2;  ///< 2: 5x5 B3 spline; 1: 3x3 binomial
  int step = 1;
  float sigmaDepth = 1.0f, depthEpsilon = 1e-2f, depthEpsilonRelative = 0.0f;
  int normalExponent = 128;
  float sigmaLuminance = 4.0f, luminanceEpsilon = 1e-10f;
  bool prefilterVariance = true, varianceScale = false, propagateVariance = true;
  const Planes* sigmaScale = nullptr;
  uint32_t luminanceMode = 0;
  /// Sparse input (AtrousLevel::validIn/validOut, shader variant atrous_masked): a pixel is
  /// valid where plane `validInPlane` of `validIn` is > 0 (a history length works as well as a
  /// 0/1 validity); `validOut` (1 plane) receives 1 where the pixel got any weight. Both null: dense.
  const Planes* validIn = nullptr;
  int validInPlane = 0;
  Planes* validOut = nullptr;
  /// Gersthofer's glossy weights (AtrousLevel's fields, shader variant atrous_glossy): z_i
  /// (1 plane) and its factor 1 - roughness (1 plane), and 1/w_r on the centre (1 plane); the
  /// first two null without w_zi. Dense input only.
  const Planes* indirectDistance = nullptr;
  const Planes* indirectDistanceScale = nullptr;
  const Planes* centreScale = nullptr;
  /// Voorhuis Eq. 6 (AtrousLevel::spatialFalloff): per-pixel c(p) (1 plane), or null.
  const Planes* spatialFalloff = nullptr;
  /// AtrousLevel::surfaceKey (1 plane), or null.
  const Planes* surfaceKey = nullptr;
  /// Read small-step taps through the shared-memory tile where the device has the 18 KiB it
  /// needs; false forces the untiled variant (tests).
  bool sharedTile = true;
};

/// The a-trous guide's depth gradient (2 planes) from the frame's depth (AtrousGuide::build).
void atrousGuide(Recorder& rec, const GpuFrame& frame, float maxDepthSlope, Planes& gradient);
/// The same from any depth plane and, where `depthGradient` is given, that gradient.
void atrousGuide(Recorder& rec, const Planes& depth, const Planes* depthGradient, float maxDepthSlope, Planes& gradient);
/// The a-trous guide's normals (excludeEmitters, src/passes/emitters.h): where the settings
/// exclude emitters and the frame has Buffer::Emission, the frame's normals with a zero normal
/// at every emitter pixel, written to `normal` (3 planes of the frame's size), which is
/// returned; otherwise the frame's own normals.
const Planes& emitterGuideNormal(Recorder& rec, const GpuFrame& frame, const EmitterSettings& s, Planes& normal);
/// One a-trous level: images of 5 planes (R, G, B, luminance, variance); `in` != `out`. The
/// guide is the frame's depth and normal and `gradient` (atrousGuide).
void atrousLevel(Recorder& rec, const GpuFrame& frame, const Planes& gradient, const GpuAtrousLevel& level,
                 const Planes& in, Planes& out);
/// The same with the guide's depth (1 plane) and normal (3 planes) given, at the images' size.
void atrousLevel(Recorder& rec, const Planes& depth, const Planes& normal, const Planes& gradient,
                 const GpuAtrousLevel& level, const Planes& in, Planes& out);
/// Clamped 3x3 Gaussian of plane `srcPlane` of `in` into plane `dstPlane` of `out`.
void gaussian3x3(Recorder& rec, const Planes& in, int srcPlane, Planes& out, int dstPlane);

/// Eye reprojection (eyeReproject in src/passes/eye_reprojection.h): out = (1 - blend) target +
/// blend * the source's light gathered at the target's world positions, where the source's
/// taps pass the tests of `s`; target elsewhere. `sourceValid` (optional): source taps need plane
/// `validPlane` > 0. The target frame needs Position and Normal, the source Normal and Depth.
void eyeReproject(Recorder& rec, const GpuFrame& target, const GpuFrame& source, const Planes* sourceValid,
                  int validPlane, const ReprojectionSettings& s, float blend, const Planes& targetLight,
                  const Planes& sourceLight, Planes& out);

/// FXAA (fxaa() in src/passes/fxaa.h) of `in` (R, G, B, fxaaLuma: 4 planes) into `out` (3 planes).
void fxaa(Recorder& rec, const Planes& in, Planes& out, float edgeThreshold = 0.166f, float edgeThresholdMin = 0.0833f,
          float subpixel = 0.75f);

/// taaSurfaceKeys (src/passes/taa_keys.h) on the device into `out` (1 plane of uint32, allocated
/// here): `cls` the surface classes (1 plane, as float) or nullptr. Returns false (nothing
/// dispatched) where the frame has nothing that tells surfaces apart.
bool taaSurfaceKeys(Recorder& rec, const GpuFrame& f, const EmitterSettings* emitters, const Planes* cls, Planes& out);

/// Karis TAA on the remodulated output; its result is the next frame's history.
class GpuTaa {
 public:
  /// A new frame size: the planes are allocated by the first run() (none where TAA is off).
  void resize(int w, int h);
  void reset() { valid_ = false; }
  /// Taa::run (src/passes/taa.h) on the device: the linear output.
  /// `keys` (1 plane of uint32, surfaceKeys()): read with s.taaOwnSurface, as Taa::run's.
  const Planes& run(Recorder& rec, const Planes& rp, const Planes& color, const TaaSettings& s,
                    const Planes* keys = nullptr);
  uint64_t bytes() const {
    return uint64_t(history_[0].buffer.size() + history_[1].buffer.size() + linear_.buffer.size());
  }

 private:
  Planes history_[2];  // display-encoded or linear, as the last frame's domain
  Planes linear_;      // display domain: the decoded output
  int width_ = 0, height_ = 0;
  int cur_ = 0;
  bool valid_ = false;
  bool display_ = false;
};

}  // namespace rtd::vk
