// rtdenoise evaluation — run several methods (and backends) on one sequence, evaluate each
// against the reference, keep per-pass timings, and write a self-contained HTML report.
#pragma once
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "rtd/denoiser.h"
#include "rtd/eval/evaluate.h"
#include "rtd/sequence.h"

namespace rtd::eval {

/// Where frames come from: a sequence on disk, the analytic scene, or the renderer.
/// `load(index, reference)` returns input frame `index` (0-based) and fills its linear HDR
/// reference (RGB).
struct FrameSource {
  std::string description;
  int frameCount = 0;
  int width = 0, height = 0;  ///< frame size when known before loading (0: unknown)
  std::function<Frame(int index, Image& reference)> load;
  /// What is known of the references' own quality, for the report.
  int referenceSpp = 0;  ///< samples per pixel of the references (0: unknown)
  bool referenceExact = false;  ///< the references are exact (an analytic scene): no noise
  std::string referenceNote;    ///< how the references were made (e.g. convergence steps)
  /// Optional: two independent half-sample estimates A, B of reference frame `index`, whose
  /// mean is the reference. Their difference estimates the reference's remaining noise.
  std::function<void(int index, Image& halfA, Image& halfB)> referenceHalves;
};

/// The reference's own quality: how far it is from the converged image, estimated from two
/// independent halves A and B (each of spp/2 samples): the variance of their mean is
/// E[(A - B)^2] / 4 per pixel, so relMSE_ref = mean((A - B)^2 / 4 / (R^2 + 0.01)) is the relMSE
/// the reference itself has against the converged image; psnr likewise on the tone-mapped
/// halves. A method whose error approaches these is limited by the reference.
struct ReferenceQuality {
  int spp = 0;
  bool exact = false;
  std::string note;
  bool estimated = false;  ///< halves were available
  double relMse = 0, psnr = 0;  ///< means over the frames after warm-up
};

/// Frame source reading an input sequence and a reference directory (RgbSequence), matched by
/// frame number. Throws rtd::Error naming the missing or mismatched file.
FrameSource directorySource(const std::filesystem::path& inputDir, const std::filesystem::path& referenceDir,
                            int maxFrames = 0);

/// One configuration of a comparison: a method, optionally on one backend, with settings.
/// Written "method[@backend][:key=value]...", e.g. "svgf", "svgf:variant=dundr",
/// "bmfr:blockSize=64", "svgf@vulkan", "svgf@vulkan:variant=dundr:sigmaNormal=32".
struct RunConfig {
  std::string method;
  bool hasBackend = false;  ///< "@backend" given; else the run uses each of CompareSettings::backends
  Backend backend = Backend::Cpu;
  std::vector<SettingAssignment> settings;  ///< in the order given (presets are applied first)
};
/// Parses a configuration; throws rtd::Error naming the text when it is malformed (the method
/// and setting names are checked when the comparison starts).
RunConfig parseRunConfig(const std::string& text);
/// The configuration as text, in the form parseRunConfig() reads.
std::string configText(const RunConfig& c);

struct CompareSettings {
  /// The configurations; empty: every method with a CPU implementation, default settings.
  std::vector<RunConfig> configs;
  /// Backends of the configurations that name none (each such configuration runs on each).
  std::vector<Backend> backends{Backend::Cpu};
  std::string vulkanDevice;  ///< Vulkan device index or name substring (empty: the best)
  /// Settings for every run: "method.setting=value" for the runs of that method, or
  /// "setting=value" for every run whose method has the setting. A configuration's own
  /// settings override these. A setting no run has is an error.
  std::vector<std::string> settings;
  int threads = 0;
  EvalSettings eval;
  bool includeInput = true;  ///< evaluate the noisy input as a row too
  int shownFrame = -1;       ///< frame index the report opens at; -1: the last
  /// The report stores every frame of every run downscaled (box filter) to at most this width.
  int reportMaxWidth = 960;
  /// Crop shown enlarged in the report (pixels, inside the image); width 0: an automatic
  /// centred crop.
  int cropX = 0, cropY = 0, cropWidth = 0, cropHeight = 0;
};

/// One evaluated stream: the input, or one method on one backend.
struct MethodRun {
  /// "input", or the configuration named by what tells it apart from the other runs: its
  /// method, its own settings ("svgf variant=dundr") and, when the runs use several
  /// backends, its backend ("svgf (vulkan)").
  std::string label;
  std::string config;   ///< the configuration as text (configText()); empty for the input
  std::string method;   ///< empty for the input
  std::string backend;  ///< empty for the input
  std::string device;
  std::vector<SettingInfo> settings;
  StreamMetrics metrics;
  std::vector<std::string> passOrder;
  std::map<std::string, std::vector<double>> passMs;  ///< per timed frame (after warm-up)
  std::vector<double> totalMs;                        ///< per frame, all frames
  /// Per frame: the tone-mapped output and its LDR-FLIP error map (magma), encoded (WebP, or
  /// PNG in a build without libwebp) at the report's display size. FLIP maps: none without FLIP.
  std::vector<std::string> frameImages, flipImages;
  double medianTotalMs() const;
  double medianPassMs(const std::string& pass) const;
};

struct Comparison {
  std::string title = "rtdenoise comparison";
  std::string source;
  int width = 0, height = 0, frames = 0;
  int shownFrame = 0;  ///< index of the frame the report opens at
  std::vector<int> frameNumbers;
  EvalSettings eval;
  std::vector<MethodRun> runs;  ///< the input first (if included), then each method/backend
  std::vector<std::string> referenceImages;  ///< per frame, encoded as MethodRun::frameImages
  int displayWidth = 0, displayHeight = 0;   ///< size of the encoded images
  std::string imageMime;                     ///< "image/webp" or "image/png"
  ReferenceQuality referenceQuality;
  int cropX = 0, cropY = 0, cropWidth = 0, cropHeight = 0;
  double seconds = 0;  ///< wall time of the whole comparison
  std::string machine; ///< CPU model
  std::vector<std::string> skipped;  ///< method/backend pairs not run (not implemented there)
};

/// Checks the configurations and settings (method and setting names, backends, labels) without
/// running anything; throws rtd::Error naming the first problem. runComparison() checks the same.
void checkCompareSettings(const CompareSettings& settings);

/// Runs every method over the source frame by frame (one denoiser per method and backend),
/// evaluating each output as it comes. `progress(done, total, detail)` after each frame.
Comparison runComparison(const FrameSource& source, const CompareSettings& settings,
                         const std::function<void(int, int, const std::string&)>& progress = {});

/// The comparison's metrics as a table, one row per run (steady-state means, median ms).
std::string comparisonTable(const Comparison& c);
/// JSON text of the comparison (settings, per-frame metrics, summaries, timings).
std::string comparisonJson(const Comparison& c);
/// A self-contained HTML report: a frame player with a before/after slider over every frame of
/// every run (images as WebP or PNG data URIs), plots as inline SVG, stacked per-pass timings.
std::string comparisonHtml(const Comparison& c);
/// Writes comparisonHtml() to `path` atomically.
void writeHtmlReport(const Comparison& c, const std::filesystem::path& path);

/// PNG encoding of an 8-bit image (sRGB-encoded floats in [0,1]); used by the report.
std::string encodePng(const Image& srgb);
/// The report's image encoding of an sRGB-encoded image: lossy WebP (quality 90) where the
/// build has libwebp, else PNG; `mime` receives its MIME type.
std::string encodeReportImage(const Image& srgb, std::string* mime = nullptr);

}  // namespace rtd::eval
