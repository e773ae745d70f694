// rtdenoise evaluation — per-frame and per-sequence metrics of a denoised sequence against a
// reference, including temporal error, with warm-up frames reported separately.
#pragma once
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rtd/eval/metrics.h"
#include "rtd/image.h"

namespace rtd::eval {

struct EvalSettings {
  ToneMapSettings toneMap;
  FlipSettings flip;
  /// The first `warmupFrames` frames of a sequence (history still filling) are averaged
  /// separately from the rest.
  int warmupFrames = 0;
  bool computeFlip = true;     ///< LDR-FLIP of the tone-mapped images
  bool computeHdrFlip = true;  ///< HDR-FLIP of the linear images (exposure bracket from the reference)
  double relMseEpsilon = 0.01;
};

/// Metrics of one frame. NaN where a metric does not apply (temporal error of the first frame).
struct FrameMetrics {
  int number = 0;
  bool warmup = false;
  double psnr = 0;    ///< dB, tone-mapped sRGB
  double ssim = 0;    ///< tone-mapped sRGB
  double flip = 0;    ///< LDR-FLIP mean, tone-mapped sRGB
  double hdrFlip = 0; ///< HDR-FLIP mean, linear HDR (exposure bracket from the reference)
  double relMse = 0;  ///< linear HDR
  double rmse = 0;    ///< linear HDR
  /// Mean |L_t - L_{t-1}| of the result's luma (tone-mapped sRGB): Schied et al. 2017.
  double temporalError = 0;
  /// The same for the reference: how much the true image changes.
  double referenceTemporalError = 0;
  /// Mean |(L_t - L_{t-1}) - (R_t - R_{t-1})|: change that the reference does not have
  /// (flicker, lag, ghosting). Zero for a perfect result, not for a frozen one.
  double temporalErrorVsReference = 0;
  /// NaN/Inf values in the result (replaced by 0 before computing the metrics, so they count
  /// as errors instead of vanishing from the means).
  uint64_t nonFiniteValues = 0;
  /// The distribution of the per-pixel FLIP and HDR-FLIP errors (NaN where not computed).
  ErrorStatistics flipPixels, hdrFlipPixels;
};

/// One metric: its JSON key, label, colour space, direction and field, so that tables, JSON and
/// the report list every metric from this one place.
struct MetricInfo {
  const char* key;
  const char* label;
  const char* space;  ///< "tone-mapped sRGB" or "linear HDR"
  bool higherIsBetter;
  double FrameMetrics::*field;
  bool temporal;  ///< undefined on the first frame
  /// Whether a lower (higher) value means a better result, so tables highlight the best. Not
  /// for the raw temporal change (a frozen image would win) nor the reference's own change:
  /// those are shown as information.
  bool ranked = true;
};
const std::vector<MetricInfo>& metricList();

/// Mean, median and quartiles of each metric over a set of frames (NaN where no frame has
/// it; quartiles interpolated between ranks as numpy.percentile).
struct MetricSummary {
  int frames = 0;
  int firstFrame = 0, lastFrame = 0;  ///< frame numbers the summary covers (0 when none)
  FrameMetrics mean;  ///< number/warmup unused
  FrameMetrics q1, median, q3;
};
MetricSummary summarize(const std::vector<FrameMetrics>& frames, bool warmup);

/// A reference frame prepared once (RGB, tone-mapped, luma, FLIP half) and evaluated against
/// several streams.
struct PreparedReference {
  int number = 0;
  Image linear;  ///< linear HDR RGB
  Image ldr;     ///< tone-mapped sRGB
  Image luma;    ///< luma of ldr
  FlipReference flip;
  HdrFlipReference hdrFlip;
};
PreparedReference prepareReference(int number, const Image& reference, const EvalSettings& settings);

/// Evaluates a stream of frames in order. Keeps the previous frame's luma for temporal error.
class SequenceEvaluator {
 public:
  explicit SequenceEvaluator(EvalSettings settings = {});
  /// `result` and `reference` are linear HDR RGB of frame `number`. `flipMap` and `hdrFlipMap`,
  /// if not null, receive the FLIP and HDR-FLIP error maps.
  const FrameMetrics& add(int number, const Image& result, const Image& reference, Image* flipMap = nullptr,
                          Image* hdrFlipMap = nullptr);
  /// Same, with the reference prepared by prepareReference() with the same settings.
  const FrameMetrics& add(const Image& result, const PreparedReference& reference, Image* flipMap = nullptr,
                          Image* hdrFlipMap = nullptr);
  /// Forget the previous frame (camera cut): the next frame has no temporal error.
  void resetTemporal();
  const std::vector<FrameMetrics>& frames() const { return frames_; }
  MetricSummary steady() const { return summarize(frames_, false); }
  MetricSummary warmup() const { return summarize(frames_, true); }
  const EvalSettings& settings() const { return settings_; }

 private:
  EvalSettings settings_;
  std::vector<FrameMetrics> frames_;
  Image prevResultLuma_, prevReferenceLuma_;
};

/// An RGB frame sequence on disk: a native sequence (its color buffer), a Blender sequence
/// (Combined), or a directory of RGB EXR files whose names end in a frame number
/// (frame_0007.exr, as `rtdenoise denoise` writes).
class RgbSequence {
 public:
  /// `role` ("reference", "result", "input") is used in error messages.
  static std::unique_ptr<RgbSequence> open(const std::filesystem::path& dir, const std::string& role);
  virtual ~RgbSequence() = default;
  virtual int frameCount() const = 0;
  virtual int frameNumber(int index) const = 0;
  virtual std::filesystem::path framePath(int index) const = 0;
  /// Index of frame `number`, or -1.
  int indexOf(int number) const;
  virtual Image read(int index) const = 0;
};

/// The metrics of one image stream (a method's output, or the noisy input) over a sequence.
struct StreamMetrics {
  std::string name;
  std::vector<FrameMetrics> frames;
  MetricSummary steady, warmup;
};

/// Evaluates `resultDir` (and `inputDir`, when given, as a second stream named "input")
/// against `referenceDir`. Frames are matched by number. The result's frames must be the
/// reference's frames, or the first N of them (a shorter run): a frame the reference lacks, a
/// gap, or a result that starts later throws. Where the result directory has `timings.json`
/// (as `rtdenoise denoise` writes), its frames must be exactly the frames listed there, so the
/// leftovers of an earlier run are never scored. Input frames must exist for every result frame.
/// Errors (rtd::Error) name the missing or mismatched file. `progress(done, total)` is called
/// after each frame.
std::vector<StreamMetrics> evaluateDirectories(const std::filesystem::path& referenceDir,
                                               const std::filesystem::path& resultDir,
                                               const std::optional<std::filesystem::path>& inputDir,
                                               const EvalSettings& settings,
                                               const std::function<void(int, int)>& progress = {});

/// A metric's value as the tables print it (PSNR 2 decimals, SSIM/FLIP 4, others 3 significant
/// digits; "-" for NaN, "inf").
std::string formatMetric(const MetricInfo& m, double v);

/// "frames 9-32 (24)": the frames a summary covers.
std::string coverage(const MetricSummary& s);

/// A fixed-width text table of the steady-state (and, if any, warm-up) means of each stream.
std::string summaryTable(const std::vector<StreamMetrics>& streams, const EvalSettings& settings);

/// JSON text: settings, per-stream per-frame metrics and summaries (non-finite numbers as
/// strings "inf"/"-inf"/"nan" never appear as JSON numbers; undefined values are null).
std::string metricsJson(const std::vector<StreamMetrics>& streams, const EvalSettings& settings);

}  // namespace rtd::eval
