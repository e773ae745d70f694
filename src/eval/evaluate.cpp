// Sequence evaluation: per-frame metrics, temporal error, warm-up split, directory matching.
#include "rtd/eval/evaluate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "rtd/error.h"
#include "rtd/sequence.h"
#include "eval/json_util.h"

namespace rtd::eval {

namespace fs = std::filesystem;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

const std::vector<MetricInfo>& metricList() {
  static const std::vector<MetricInfo> list = {
      {"psnr", "PSNR [dB]", "tone-mapped sRGB", true, &FrameMetrics::psnr, false},
      {"ssim", "SSIM", "tone-mapped sRGB", true, &FrameMetrics::ssim, false},
      {"flip", "FLIP", "tone-mapped sRGB", false, &FrameMetrics::flip, false},
      {"hdrFlip", "HDR-FLIP", "linear HDR, exposure bracket", false, &FrameMetrics::hdrFlip, false},
      {"relMse", "relMSE", "linear HDR", false, &FrameMetrics::relMse, false},
      {"rmse", "RMSE", "linear HDR", false, &FrameMetrics::rmse, false},
      {"temporalErrorVsReference", "temporal vs ref", "tone-mapped sRGB luma", false,
       &FrameMetrics::temporalErrorVsReference, true},
      {"temporalError", "temporal change", "tone-mapped sRGB luma", false, &FrameMetrics::temporalError, true, false},
      {"referenceTemporalError", "ref temporal change", "tone-mapped sRGB luma", false,
       &FrameMetrics::referenceTemporalError, true, false},
  };
  return list;
}

MetricSummary summarize(const std::vector<FrameMetrics>& frames, bool warmup) {
  MetricSummary s;
  for (const auto& m : metricList()) {
    std::vector<double> v;
    for (const auto& f : frames)
      if (f.warmup == warmup && !std::isnan(f.*m.field)) v.push_back(f.*m.field);
    if (v.empty()) {
      s.mean.*m.field = s.q1.*m.field = s.median.*m.field = s.q3.*m.field = kNaN;
      continue;
    }
    double sum = 0;
    for (double x : v) sum += x;
    s.mean.*m.field = sum / double(v.size());
    std::sort(v.begin(), v.end());
    const auto at = [&](double q) {  // numpy.percentile's default ('linear')
      const double pos = q * double(v.size() - 1);
      const size_t lo = size_t(pos), hi = std::min(lo + 1, v.size() - 1);
      return v[lo] + (pos - double(lo)) * (v[hi] - v[lo]);
    };
    s.q1.*m.field = at(0.25);
    s.median.*m.field = at(0.5);
    s.q3.*m.field = at(0.75);
  }
  for (const auto& f : frames) {
    if (f.warmup != warmup) continue;
    if (s.frames++ == 0) s.firstFrame = f.number;
    s.lastFrame = f.number;
    s.mean.nonFiniteValues += f.nonFiniteValues;
  }
  return s;
}

SequenceEvaluator::SequenceEvaluator(EvalSettings settings) : settings_(std::move(settings)) {}

void SequenceEvaluator::resetTemporal() {
  prevResultLuma_ = Image();
  prevReferenceLuma_ = Image();
}

namespace {
Image rgbOnly(const Image& img) {
  if (img.channels == 3) return img;
  if (img.channels < 3) throw Error("expected an RGB image, got " + std::to_string(img.channels) + " channel(s)");
  Image out(img.width, img.height, 3);
  for (size_t i = 0; i < size_t(img.width) * img.height; ++i)
    for (int c = 0; c < 3; ++c) out.pixels[i * 3 + c] = img.pixels[i * img.channels + c];
  return out;
}
}  // namespace

PreparedReference prepareReference(int number, const Image& reference, const EvalSettings& settings) {
  PreparedReference p;
  p.number = number;
  p.linear = rgbOnly(reference);
  p.ldr = toneMap(p.linear, settings.toneMap);
  p.luma = luminance(p.ldr);
  if (settings.computeFlip) p.flip = FlipReference(p.ldr, settings.flip);
  if (settings.computeHdrFlip) p.hdrFlip = HdrFlipReference(p.linear, settings.flip);
  return p;
}

const FrameMetrics& SequenceEvaluator::add(int number, const Image& result, const Image& reference, Image* flipMap,
                                           Image* hdrFlipMap) {
  if (result.width != reference.width || result.height != reference.height)
    throw Error("frame " + std::to_string(number) + ": result is " + std::to_string(result.width) + "x" +
                std::to_string(result.height) + " but reference is " + std::to_string(reference.width) + "x" +
                std::to_string(reference.height));
  return add(result, prepareReference(number, reference, settings_), flipMap, hdrFlipMap);
}

const FrameMetrics& SequenceEvaluator::add(const Image& result, const PreparedReference& ref, Image* flipMap,
                                           Image* hdrFlipMap) {
  if (result.width != ref.linear.width || result.height != ref.linear.height)
    throw Error("frame " + std::to_string(ref.number) + ": result is " + std::to_string(result.width) + "x" +
                std::to_string(result.height) + " but reference is " + std::to_string(ref.linear.width) + "x" +
                std::to_string(ref.linear.height));
  FrameMetrics m;
  m.number = ref.number;
  m.warmup = int(frames_.size()) < settings_.warmupFrames;
  Image resultHdr = rgbOnly(result);
  for (float& v : resultHdr.pixels)
    if (!std::isfinite(v)) {
      v = 0.0f;
      ++m.nonFiniteValues;
    }
  const Image resultLdr = toneMap(resultHdr, settings_.toneMap);

  m.psnr = psnr(resultLdr, ref.ldr);
  m.ssim = ssim(resultLdr, ref.ldr);
  const ErrorStatistics none{kNaN, kNaN, kNaN, kNaN};
  m.flipPixels = m.hdrFlipPixels = none;
  Image map;
  if (settings_.computeFlip && !ref.flip.empty()) {
    ref.flip.compare(resultLdr, &map);
    m.flipPixels = errorStatistics(map);
    if (flipMap) *flipMap = std::move(map);
  }
  if (settings_.computeHdrFlip && !ref.hdrFlip.empty()) {
    ref.hdrFlip.compare(resultHdr, &map);
    m.hdrFlipPixels = errorStatistics(map);
    if (hdrFlipMap) *hdrFlipMap = std::move(map);
  }
  m.flip = m.flipPixels.mean;
  m.hdrFlip = m.hdrFlipPixels.mean;
  m.relMse = relMse(resultHdr, ref.linear, settings_.relMseEpsilon);
  m.rmse = rmse(resultHdr, ref.linear);

  // Temporal error (Schied et al. 2017): mean absolute luma change between consecutive frames.
  Image lr = luminance(resultLdr);
  const Image& lf = ref.luma;
  if (!prevResultLuma_.empty() && prevResultLuma_.width == lr.width && prevResultLuma_.height == lr.height) {
    double raw = 0, refSum = 0, vs = 0;
    for (size_t i = 0; i < lr.pixels.size(); ++i) {
      const double dr = double(lr.pixels[i]) - prevResultLuma_.pixels[i];
      const double df = double(lf.pixels[i]) - prevReferenceLuma_.pixels[i];
      raw += std::abs(dr);
      refSum += std::abs(df);
      vs += std::abs(dr - df);
    }
    const double n = double(lr.pixels.size());
    m.temporalError = raw / n;
    m.referenceTemporalError = refSum / n;
    m.temporalErrorVsReference = vs / n;
  } else {
    m.temporalError = m.referenceTemporalError = m.temporalErrorVsReference = kNaN;
  }
  prevResultLuma_ = std::move(lr);
  prevReferenceLuma_ = lf;
  frames_.push_back(m);
  return frames_.back();
}

// ---------------------------------------------------------------------------------------------

int RgbSequence::indexOf(int number) const {
  for (int i = 0; i < frameCount(); ++i)
    if (frameNumber(i) == number) return i;
  return -1;
}

namespace {
/// A native or Blender sequence: the color buffer.
class ReaderSequence final : public RgbSequence {
 public:
  explicit ReaderSequence(std::unique_ptr<SequenceReader> r) : r_(std::move(r)) {}
  int frameCount() const override { return r_->frameCount(); }
  int frameNumber(int i) const override { return r_->frameNumber(i); }
  fs::path framePath(int i) const override { return r_->framePath(i); }
  Image read(int i) const override {
    Frame f = r_->read(i);
    if (!f.has(Buffer::Color)) throw Error("'" + framePath(i).string() + "' has no color buffer");
    return std::move(f[Buffer::Color]);
  }

 private:
  std::unique_ptr<SequenceReader> r_;
};

/// A directory of RGB EXR files named <anything><digits>.exr.
class ExrFilesSequence final : public RgbSequence {
 public:
  explicit ExrFilesSequence(std::vector<std::pair<int, fs::path>> files) : files_(std::move(files)) {}
  int frameCount() const override { return int(files_.size()); }
  int frameNumber(int i) const override { return files_[i].first; }
  fs::path framePath(int i) const override { return files_[i].second; }
  Image read(int i) const override { return readRgbExr(files_[i].second); }

 private:
  std::vector<std::pair<int, fs::path>> files_;
};

std::optional<int> trailingNumber(const std::string& stem) {
  size_t end = stem.size(), begin = end;
  while (begin > 0 && std::isdigit(static_cast<unsigned char>(stem[begin - 1]))) --begin;
  if (begin == end || end - begin > 9) return std::nullopt;
  return std::stoi(stem.substr(begin));
}
}  // namespace

std::unique_ptr<RgbSequence> RgbSequence::open(const fs::path& dir, const std::string& role) {
  if (!fs::is_directory(dir)) throw Error(role + " directory '" + dir.string() + "' does not exist");
  if (fs::exists(dir / "sequence.json")) return std::make_unique<ReaderSequence>(SequenceReader::open(dir));
  std::vector<std::pair<int, fs::path>> files;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (!e.is_regular_file() || e.path().extension() != ".exr") continue;
    if (auto n = trailingNumber(e.path().stem().string())) files.emplace_back(*n, e.path());
  }
  if (files.empty()) throw Error(role + " directory '" + dir.string() + "' holds no frame EXR files (frame_NNNN.exr)");
  std::sort(files.begin(), files.end());
  for (size_t i = 1; i < files.size(); ++i)
    if (files[i].first == files[i - 1].first)
      throw Error(role + " directory '" + dir.string() + "': '" + files[i - 1].second.filename().string() + "' and '" +
                  files[i].second.filename().string() + "' have the same frame number");
  // Blender multilayer files have no top-level R, G, B: read them as a Blender sequence.
  try {
    (void)readRgbExr(files.front().second);
  } catch (const Error&) {
    return std::make_unique<ReaderSequence>(SequenceReader::open(dir));
  }
  return std::make_unique<ExrFilesSequence>(std::move(files));
}

namespace {
/// The result's frames are the reference's (or its first N), and those `timings.json` lists.
void checkResultFrames(const RgbSequence& result, const RgbSequence& reference, const fs::path& resultDir,
                       const fs::path& referenceDir) {
  const int n = result.frameCount();
  const auto listed = [](const RgbSequence& s) {
    const int count = s.frameCount();
    if (count == 0) return std::string("no frames");
    std::string text = std::to_string(count) + " frame(s), " + std::to_string(s.frameNumber(0));
    bool consecutive = true;
    for (int i = 1; i < count; ++i) consecutive &= s.frameNumber(i) == s.frameNumber(i - 1) + 1;
    return text + (count > 1 ? (consecutive ? "-" : " ... ") + std::to_string(s.frameNumber(count - 1)) : std::string());
  };
  const std::string mismatch = "the result's frames (" + listed(result) + " in '" + resultDir.string() +
                               "') do not match the reference's (" + listed(reference) + " in '" + referenceDir.string() + "')";
  for (int i = 0; i < n; ++i) {
    if (i < reference.frameCount() && result.frameNumber(i) == reference.frameNumber(i)) continue;
    if (i >= reference.frameCount() || result.frameNumber(i) < reference.frameNumber(i))
      throw Error(mismatch + ": reference: no frame " + std::to_string(result.frameNumber(i)) + " in '" +
                  referenceDir.string() + "' for result frame '" + result.framePath(i).string() + "'");
    throw Error(mismatch + ": result: frame " + std::to_string(reference.frameNumber(i)) + " is missing before '" +
                result.framePath(i).string() + "' (a result must cover the reference's frames from the first on)");
  }
  // timings.json (rtdenoise denoise) lists the frames its run wrote.
  const fs::path timings = resultDir / "timings.json";
  if (!fs::exists(timings)) return;
  nlohmann::json j;
  try {
    std::ifstream in(timings);
    j = nlohmann::json::parse(in);
  } catch (const std::exception& e) {
    throw Error("'" + timings.string() + "' is not valid JSON: " + e.what());
  }
  if (!j.contains("frames") || !j["frames"].is_array()) return;
  std::vector<int> written;
  for (const auto& f : j["frames"])
    if (f.contains("number") && f["number"].is_number_integer()) written.push_back(f["number"].get<int>());
  std::vector<int> present;
  for (int i = 0; i < n; ++i) present.push_back(result.frameNumber(i));
  std::sort(written.begin(), written.end());
  if (written != present)
    throw Error("result '" + resultDir.string() + "' holds " + std::to_string(present.size()) + " frame file(s) but its timings.json lists " +
                std::to_string(written.size()) + " frame(s) written by its run: the directory mixes runs (denoise again with --overwrite)");
}
}  // namespace

std::vector<StreamMetrics> evaluateDirectories(const fs::path& referenceDir, const fs::path& resultDir,
                                               const std::optional<fs::path>& inputDir, const EvalSettings& settings,
                                               const std::function<void(int, int)>& progress) {
  auto reference = RgbSequence::open(referenceDir, "reference");
  auto result = RgbSequence::open(resultDir, "result");
  std::unique_ptr<RgbSequence> input;
  if (inputDir) input = RgbSequence::open(*inputDir, "input");

  const int n = result->frameCount();
  checkResultFrames(*result, *reference, resultDir, referenceDir);
  std::vector<int> refIndex(n), inIndex(n, -1);
  for (int i = 0; i < n; ++i) {
    const int number = result->frameNumber(i);
    refIndex[i] = reference->indexOf(number);
    if (input) {
      inIndex[i] = input->indexOf(number);
      if (inIndex[i] < 0)
        throw Error("input: no frame " + std::to_string(number) + " in '" + inputDir->string() +
                    "' for result frame '" + result->framePath(i).string() + "'");
    }
  }

  SequenceEvaluator resultEval(settings), inputEval(settings);
  for (int i = 0; i < n; ++i) {
    const Image ref = reference->read(refIndex[i]);
    const auto check = [&](const Image& img, const RgbSequence& seq, int index) {
      if (img.width != ref.width || img.height != ref.height)
        throw Error("'" + seq.framePath(index).string() + "' is " + std::to_string(img.width) + "x" +
                    std::to_string(img.height) + " but reference '" + reference->framePath(refIndex[i]).string() +
                    "' is " + std::to_string(ref.width) + "x" + std::to_string(ref.height));
    };
    const Image res = result->read(i);
    check(res, *result, i);
    const PreparedReference prepared = prepareReference(result->frameNumber(i), ref, settings);
    resultEval.add(res, prepared);
    if (input) {
      const Image in = input->read(inIndex[i]);
      check(in, *input, inIndex[i]);
      inputEval.add(in, prepared);
    }
    if (progress) progress(i + 1, n);
  }
  std::vector<StreamMetrics> out;
  out.push_back({"result", resultEval.frames(), resultEval.steady(), resultEval.warmup()});
  if (input) out.push_back({"input", inputEval.frames(), inputEval.steady(), inputEval.warmup()});
  return out;
}

// ---------------------------------------------------------------------------------------------

std::string formatMetric(const MetricInfo& m, double v) {
  char buf[32];
  if (std::isnan(v)) return "-";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  if (std::string(m.key) == "psnr")
    std::snprintf(buf, sizeof buf, "%.2f", v);
  else if (std::string(m.key) == "ssim" || std::string(m.key) == "flip" || std::string(m.key) == "hdrFlip")
    std::snprintf(buf, sizeof buf, "%.4f", v);
  else
    std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

namespace {

std::string tableFor(const std::vector<StreamMetrics>& streams, bool warmup) {
  // Columns as wide as their labels (and the names: a configuration's label tells runs apart).
  int nameWidth = 6;
  for (const auto& s : streams) nameWidth = std::max(nameWidth, int(s.name.size()));
  const auto cell = [](const std::string& text, int width, bool left = false) {
    std::string pad(size_t(std::max(0, width - int(text.size()))), ' ');
    return left ? text + pad : pad + text;
  };
  std::string out = cell("", nameWidth, true) + " " + cell("frames", 6);
  for (const auto& m : metricList()) out.append(" ").append(cell(m.label, std::max(8, int(std::string(m.label).size()))));
  out += "\n";
  for (const auto& s : streams) {
    const MetricSummary& sum = warmup ? s.warmup : s.steady;
    out += cell(s.name, nameWidth, true) + " " + cell(std::to_string(sum.frames), 6);
    for (const auto& m : metricList())
      out.append(" ").append(cell(formatMetric(m, sum.mean.*m.field), std::max(8, int(std::string(m.label).size()))));
    if (sum.mean.nonFiniteValues) out += "  (" + std::to_string(sum.mean.nonFiniteValues) + " NaN/Inf values, counted as 0)";
    out += "\n";
  }
  return out;
}

nlohmann::json number(double v) {
  if (std::isnan(v)) return nullptr;
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return v;
}
}  // namespace

std::string coverage(const MetricSummary& s) {
  if (s.frames == 0) return "no frames";
  return (s.frames == 1 ? "frame " + std::to_string(s.firstFrame)
                        : "frames " + std::to_string(s.firstFrame) + "-" + std::to_string(s.lastFrame)) +
         " (" + std::to_string(s.frames) + ")";
}

std::string summaryTable(const std::vector<StreamMetrics>& streams, const EvalSettings& settings) {
  if (streams.empty()) return "";
  std::string out = "mean over " + coverage(streams.front().steady) + ", after " + std::to_string(settings.warmupFrames) +
                    " warm-up frame(s):\n";
  out += tableFor(streams, false);
  if (settings.warmupFrames > 0) {
    out += "mean over the warm-up, " + coverage(streams.front().warmup) + ":\n";
    out += tableFor(streams, true);
  }
  out += "(PSNR, SSIM, FLIP and the temporal columns on " + operatorName(settings.toneMap.op) +
         "-tone-mapped sRGB; HDR-FLIP, relMSE, RMSE on linear HDR. 'temporal vs ref' is the mean |difference| between "
         "the result's and the reference's frame-to-frame luma change (lower is better); 'temporal change' and "
         "'ref temporal change' are the raw mean |luma change| of the result and the reference, shown as "
         "information: a frozen image has none)\n";
  return out;
}

nlohmann::json summaryJson(const MetricSummary& s) {
  nlohmann::json j = {{"frames", s.frames}, {"nonFiniteValues", s.mean.nonFiniteValues}};
  if (s.frames) j["frameRange"] = {s.firstFrame, s.lastFrame};
  nlohmann::json quartiles = nlohmann::json::object();
  for (const auto& m : metricList()) {
    j[m.key] = number(s.mean.*m.field);
    quartiles[m.key] = {number(s.q1.*m.field), number(s.median.*m.field), number(s.q3.*m.field)};
  }
  j["quartiles"] = quartiles;
  return j;
}

nlohmann::json framesJson(const std::vector<FrameMetrics>& frames) {
  nlohmann::json arr = nlohmann::json::array();
  for (const auto& f : frames) {
    nlohmann::json j = {{"number", f.number}, {"warmup", f.warmup}, {"nonFiniteValues", f.nonFiniteValues}};
    for (const auto& m : metricList()) j[m.key] = number(f.*m.field);
    const auto pixels = [](const ErrorStatistics& e) { return nlohmann::json{number(e.q1), number(e.median), number(e.q3)}; };
    j["flipPixelQuartiles"] = pixels(f.flipPixels);
    j["hdrFlipPixelQuartiles"] = pixels(f.hdrFlipPixels);
    arr.push_back(j);
  }
  return arr;
}

nlohmann::json settingsJson(const EvalSettings& s) {
  nlohmann::json metrics = nlohmann::json::object();
  for (const auto& m : metricList())
    metrics[m.key] = {{"label", m.label}, {"space", m.space}, {"higherIsBetter", m.higherIsBetter}};
  return {{"toneMap", operatorName(s.toneMap.op)},
          {"exposure", s.toneMap.exposure},
          {"warmupFrames", s.warmupFrames},
          {"flipPixelsPerDegree", s.flip.pixelsPerDegree()},
          {"flip", s.computeFlip}, {"hdrFlip", s.computeHdrFlip},
          {"quartiles", "summaries' quartiles are [first quartile, median, third quartile] over frames; frames' "
                        "flipPixelQuartiles over the pixels of the error map (numpy.percentile interpolation)"},
          {"relMseEpsilon", s.relMseEpsilon},
          {"metrics", metrics}};
}

std::string metricsJson(const std::vector<StreamMetrics>& streams, const EvalSettings& settings) {
  nlohmann::json j = {{"settings", settingsJson(settings)}, {"streams", nlohmann::json::array()}};
  for (const auto& s : streams)
    j["streams"].push_back({{"name", s.name},
                            {"steady", summaryJson(s.steady)},
                            {"warmup", summaryJson(s.warmup)},
                            {"frames", framesJson(s.frames)}});
  return j.dump(1);
}

}  // namespace rtd::eval
