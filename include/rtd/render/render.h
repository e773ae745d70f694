// rtdenoise renderer — a CPU path tracer (Embree 3 + oneTBB) that produces the inputs every
// denoiser consumes (1-spp radiance plus noise-free feature buffers) and high-sample references.
// Scenes: built-in procedural scenes, glTF 2.0 files, or a JSON scene/sequence description
// (docs/renderer.md). Frames come out as rtd::Frame in the native buffer conventions
// (include/rtd/frame.h).
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "rtd/guide_rays.h"
#include "rtd/sequence.h"

namespace rtd::render {

/// Largest per-pixel seed + 1: seeds are kept to 24 bits so the `seed` buffer (float) holds them
/// exactly (every integer below 2^24 is a float).
constexpr uint32_t kSeedLimit = 1u << 24;

/// Which view of a stereo pair is rendered. Center is the ordinary mono camera; Left/Right are
/// shifted by -/+ eyeDistance/2 along the camera's right axis (parallel stereo).
enum class Eye { Center, Left, Right };

/// Everything that controls how a frame is rendered. Defaults are the ones the CLI uses.
struct RenderSettings {
  int width = 320;   ///< image width in pixels (a scene description may set it; the CLI overrides)
  int height = 180;  ///< image height in pixels
  int spp = 1;       ///< samples per pixel of the noisy `color` buffer (the denoisers' input: 1)
  /// Longest path in scattering events after the primary hit (1 = direct light only). With
  /// Russian roulette, 8 loses < 1% energy in typical scenes.
  int maxDepth = 8;
  /// Russian roulette starts after this many bounces (paths shorter than this are never killed).
  int russianRouletteDepth = 3;
  /// Global seed: the same seed and settings give bit-identical frames on any thread count.
  uint32_t seed = 1;
  /// Jitter the primary ray inside the pixel. Off by default: every sample then goes through the
  /// pixel centre, so the feature buffers are exactly those of the shaded point and the
  /// reference is the expectation of the 1-spp input (no anti-aliasing in either).
  bool pixelJitter = false;
  /// Fraction of pixels traced per frame (sparse sampling, Dundr 2018): 1 traces every pixel;
  /// 1/k traces a rotating blue-noise mask so that every pixel is traced once in k frames.
  /// Untraced pixels get color = 0 and sampleMask = 0; feature buffers are always complete.
  float sampleFraction = 1.0f;
  /// Distance between the eyes of a stereo pair, in world units (Eye::Left/Right only).
  float eyeDistance = 0.064f;
  /// A synthetic head-mounted display's hidden-area mesh (Gersthofer Sec. 3.1): pixels outside
  /// the lens circle (radius 1.086 in NDC units, about 12 % of the image) and, for Eye::Left /
  /// Eye::Right, a nose notch in the inner bottom corner (about 3 % more) are neither traced nor
  /// shaded: all their buffers are 0 but `hiddenArea` = 1, and their reference is 0.
  bool hiddenArea = false;
  /// Radiance of a single path is clamped to this luminance (0 = no clamp). Off by default so
  /// the renderer stays unbiased; references are never clamped.
  float clampLuminance = 0.0f;
  /// Write the split buffers (direct/indirect, diffuse/specular) and the reflection, seed and
  /// mask buffers in addition to color and the standard features.
  bool allBuffers = true;
  /// With allBuffers and without pixelJitter: A-SVGF's gradient samples (gradientSample,
  /// gradientPrevious, gradientCurrent; docs/renderer.md), one re-shaded sample of the previous
  /// frame per 3x3 stratum. Costs about 1/9 more paths.
  bool gradientSamples = true;
  /// Supersampling with guide rays (Voorhuis 2018, Sec. 5): with spp > 1, `color` and the split
  /// buffers hold only sample 0, traced through the pixel centre (the guide ray), and
  /// render(index, eye, &samples) returns samples 1 .. spp-1, jittered inside the pixel, with
  /// their own primary hits' depth and normal (include/rtd/guide_rays.h).
  bool guideRays = false;
};

/// A loaded scene with its animation: meshes, materials, lights, camera path, frame count.
class Scene {
 public:
  /// Loads a built-in scene by name (builtinScenes()), a .gltf/.glb file or a .json scene
  /// description. Errors (rtd::Error) name the file and the offending field.
  static std::shared_ptr<Scene> load(const std::string& nameOrPath);
  /// Parses a JSON scene description given as text; relative paths resolve against `baseDir`.
  static std::shared_ptr<Scene> fromJson(const std::string& text, const std::filesystem::path& baseDir,
                                         const std::string& sourceName = "<json>");
  /// Names of the built-in procedural scenes (no files needed).
  static std::vector<std::string> builtinScenes();
  /// The JSON description of a built-in scene (an example of the format); empty if unknown.
  static std::string builtinDescription(const std::string& name);

  virtual ~Scene() = default;
  /// Frame count, resolution and render settings the description asked for (defaults otherwise).
  virtual int frameCount() const = 0;
  virtual RenderSettings suggestedSettings() const = 0;
  /// A string that changes whenever anything that affects the rendered radiance changes
  /// (used as the reference-cache key together with the settings).
  virtual std::string contentHash() const = 0;
  virtual std::string name() const = 0;
};

/// Statistics of the last render call.
struct RenderStats {
  double seconds = 0;       ///< wall time of the call
  uint64_t rays = 0;        ///< rays traced (primary, bounce, shadow and feature rays)
  double raysPerSecond() const { return seconds > 0 ? double(rays) / seconds : 0.0; }
  int samplesPerPixel = 0;  ///< for references: samples actually taken
};

/// Renders frames of a scene. One call at a time per Renderer (each call is parallel inside);
/// rendering uses the calling thread's oneTBB arena (limit it with tbb::global_control or
/// tbb::task_arena). The geometry of the last few frames is kept between calls.
class Renderer {
 public:
  Renderer(std::shared_ptr<const Scene> scene, RenderSettings settings);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  const RenderSettings& settings() const;

  /// Frame `index` (0-based; Frame::number = index + 1): noisy color at settings().spp and every
  /// feature buffer (see docs/renderer.md for the list and conventions), camera matrices set.
  Frame render(int index, Eye eye = Eye::Center);
  /// With settings().guideRays: the frame of the guide rays, and in `samples` its non-guide
  /// samples (spp - 1 of them; none at spp 1).
  Frame render(int index, Eye eye, GuideRaySamples& samples);

  /// Progressive reference of frame `index`: `spp` samples per pixel (stopping early, at a
  /// multiple of the batch, once `secondsBudget` > 0 is exceeded). Returns RGB radiance;
  /// stats().samplesPerPixel says how many samples were taken. Independent of render()'s
  /// random numbers (a different seed stream).
  Image renderReference(int index, int spp, double secondsBudget = 0, Eye eye = Eye::Center);

  /// Re-shades pixel (x, y) of frame `index` with the random numbers of `seed` (a value of a
  /// `seed` buffer): one sample, exactly as render() computes it for that seed. Re-shading a
  /// previous frame's seed in the current frame gives A-SVGF's gradient samples.
  std::array<float, 3> shadePixel(int index, int x, int y, uint32_t seed, Eye eye = Eye::Center);

  /// The per-pixel seed render() uses for pixel (x, y) of frame `index` (< kSeedLimit).
  uint32_t pixelSeed(int index, int x, int y, Eye eye = Eye::Center) const;

  /// Whether pixel (x, y) of `eye` lies under the synthetic hidden-area mesh (settings().hiddenArea).
  bool hidden(int x, int y, Eye eye = Eye::Center) const;

  /// Whether pixel (x, y) is traced in frame `index` by `eye` under settings().sampleFraction
  /// (the right eye's masks are disjoint from the left eye's for fractions <= 1/2).
  bool sampleMask(int index, int x, int y, Eye eye = Eye::Center) const;

  const RenderStats& stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Where and how references are cached: one EXR per (scene content, settings, frame, spp, eye),
/// named by a hash, so a reference is never rendered twice.
struct ReferenceCache {
  std::filesystem::path dir;  ///< empty: no caching
  /// The default cache directory: $RTD_CACHE_DIR, else $XDG_CACHE_HOME/rtdenoise/references,
  /// else ~/.cache/rtdenoise/references.
  static std::filesystem::path defaultDir();
  /// The cache file of a reference (whether or not it exists yet). A time-budgeted reference
  /// (budgetSeconds > 0) is cached under a key of its own, since its sample count varies.
  std::filesystem::path entry(const Scene& scene, const RenderSettings& s, int index, int spp, Eye eye,
                              double budgetSeconds = 0) const;
  /// The reference of frame `index`: read from the cache when a readable entry of the right
  /// size exists (`*cached` = true), else rendered with `r.renderReference` and stored (a damaged
  /// entry is rendered again and overwritten). With an empty `dir`, always rendered.
  Image fetchOrRender(Renderer& r, const Scene& scene, int index, int spp, double budgetSeconds, Eye eye,
                      bool* cached = nullptr) const;
};

/// Name of an eye ("center", "left", "right").
const char* eyeName(Eye eye);

}  // namespace rtd::render
