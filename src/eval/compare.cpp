// Running several methods on one sequence and evaluating them side by side.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "eval/json_util.h"
#include "rtd/eval/compare.h"

namespace rtd::eval {

namespace fs = std::filesystem;

namespace {
double median(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string cpuModel() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      if (colon != std::string::npos) return line.substr(line.find_first_not_of(' ', colon + 1));
    }
  return "unknown CPU";
}

bool hasSetting(const MethodInfo& m, const std::string& key) {
  return std::any_of(m.settings.begin(), m.settings.end(), [&](const SettingInfo& s) { return s.name == key; });
}

const MethodInfo& methodNamed(const std::vector<MethodInfo>& methods, const std::string& name, const std::string& where) {
  for (const auto& m : methods)
    if (m.name == name) return m;
  std::string names;
  for (const auto& m : methods) names += (names.empty() ? "" : ", ") + m.name;
  throw Error(where + ": no method '" + name + "' (methods: " + names + ")");
}

/// One run to make: a configuration on one backend, with every setting it gets.
struct PlannedRun {
  RunConfig config;
  Backend backend;
  std::vector<SettingAssignment> settings;  ///< global settings that concern it, then its own
};

/// Expands the configurations over the backends and distributes the global settings; every
/// name is checked here, before anything runs.
std::vector<PlannedRun> planRuns(const CompareSettings& cs, std::vector<std::string>& skipped) {
  const auto methods = listMethods();
  std::vector<RunConfig> configs = cs.configs;
  if (configs.empty())
    for (const auto& m : methods)
      if (m.cpu) configs.push_back({m.name, false, Backend::Cpu, {}});
  if (cs.backends.empty()) throw Error("comparison: no backend given");

  std::vector<PlannedRun> plan;
  for (const auto& c : configs) {
    const MethodInfo& info = methodNamed(methods, c.method, "configuration '" + configText(c) + "'");
    for (const auto& [key, value] : c.settings)
      if (!hasSetting(info, key))
        throw Error("configuration '" + configText(c) + "': method '" + c.method + "' has no setting '" + key +
                    "' (see `rtdenoise methods " + c.method + "`)");
    const std::vector<Backend> backends = c.hasBackend ? std::vector<Backend>{c.backend} : cs.backends;
    for (Backend b : backends) {
      const bool implemented = b == Backend::Cpu ? info.cpu : info.vulkan;
      if (!implemented) {
        // Skipped (and noted) when another backend of the list runs it, so `--backend cpu,vulkan`
        // compares what exists on both; an error when nothing would run it.
        if (!c.hasBackend && backends.size() > 1) {
          skipped.push_back(configText(c) + " on " + std::string(backendName(b)) + ": not implemented on this backend");
          continue;
        }
        throw Error("configuration '" + configText(c) + "': method '" + c.method + "' has no " +
                    std::string(backendName(b)) + " implementation");
      }
      plan.push_back({c, b, {}});
    }
  }

  // Global settings: "method.key=value" or "key=value"; each must reach at least one run.
  for (const auto& text : cs.settings) {
    const auto eq = text.find('=');
    if (eq == std::string::npos || eq == 0) throw Error("setting '" + text + "': expected method.key=value or key=value");
    const std::string key = text.substr(0, eq), value = text.substr(eq + 1);
    bool used = false;
    for (auto& run : plan) {
      const MethodInfo& info = methodNamed(methods, run.config.method, "configuration");
      std::string k = key;
      // "svgf.sigmaNormal": for svgf runs; a dotted name of the method's own wins over that reading.
      const auto dot = key.find('.');
      if (!hasSetting(info, key) && dot != std::string::npos) {
        if (key.substr(0, dot) != run.config.method) continue;
        k = key.substr(dot + 1);
      }
      if (!hasSetting(info, k)) continue;
      const bool own = std::any_of(run.config.settings.begin(), run.config.settings.end(),
                                   [&](const SettingAssignment& a) { return a.first == k; });
      if (!own) run.settings.emplace_back(k, value);
      used = true;
    }
    if (!used) throw Error("setting '" + text + "': no method in the comparison has a setting '" + key + "'");
  }
  for (auto& run : plan) run.settings.insert(run.settings.end(), run.config.settings.begin(), run.config.settings.end());
  return plan;
}

/// Labels: the method, then the configuration's own settings, then the backend when the runs
/// use more than one. Two runs with one label are the same configuration listed twice.
std::vector<std::string> labelRuns(const std::vector<PlannedRun>& plan) {
  bool severalBackends = false;
  for (const auto& r : plan) severalBackends |= r.backend != plan.front().backend;
  std::vector<std::string> labels;
  for (const auto& r : plan) {
    std::string label = r.config.method;
    for (const auto& [k, v] : r.config.settings) label += " " + k + "=" + v;
    if (severalBackends) label += " (" + std::string(backendName(r.backend)) + ")";
    if (std::find(labels.begin(), labels.end(), label) != labels.end())
      throw Error("configuration '" + configText(r.config) + "' is listed twice");
    labels.push_back(label);
  }
  return labels;
}

/// Box-filter downscale by an integer factor (the last block of a row or column may be partial).
Image downscale(const Image& img, int factor) {
  if (factor <= 1) return img;
  const int w = (img.width + factor - 1) / factor, h = (img.height + factor - 1) / factor;
  Image out(w, h, img.channels, 0.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int x1 = std::min(img.width, (x + 1) * factor), y1 = std::min(img.height, (y + 1) * factor);
      const float n = float((x1 - x * factor) * (y1 - y * factor));
      for (int yy = y * factor; yy < y1; ++yy)
        for (int xx = x * factor; xx < x1; ++xx)
          for (int c = 0; c < img.channels; ++c) {
            const float v = img.at(xx, yy, c);
            out.at(x, y, c) += (std::isfinite(v) ? v : 0.0f) / n;
          }
    }
  return out;
}

/// The reference's own error from two independent halves A, B (ReferenceQuality): relMSE
/// mean((A-B)^2 / 4 / (R^2 + eps)) on linear HDR and PSNR from MSE(tm(A), tm(B)) / 4.
std::pair<double, double> referenceNoise(const Image& a, const Image& b, const Image& reference, const EvalSettings& s) {
  if (a.width != reference.width || b.width != reference.width || a.height != reference.height || b.height != reference.height)
    throw Error("comparison: the reference halves differ in size from the reference");
  double rel = 0;
  size_t n = 0;
  for (int y = 0; y < reference.height; ++y)
    for (int x = 0; x < reference.width; ++x)
      for (int c = 0; c < 3; ++c, ++n) {
        const double d = double(a.at(x, y, c)) - b.at(x, y, c), r = reference.at(x, y, c);
        rel += d * d / 4.0 / (r * r + s.relMseEpsilon);
      }
  const double m = mse(toneMap(a, s.toneMap), toneMap(b, s.toneMap)) / 4.0;
  return {rel / double(std::max<size_t>(n, 1)), m > 0 ? 10.0 * std::log10(1.0 / m) : kInfinity};
}

struct Runner {
  MethodRun run;
  std::unique_ptr<Denoiser> denoiser;  // null for the input
  SequenceEvaluator evaluator;
  Image output;
};
}  // namespace

RunConfig parseRunConfig(const std::string& text) {
  RunConfig c;
  std::vector<std::string> parts;
  size_t start = 0;
  for (size_t i = 0; i <= text.size(); ++i)
    if (i == text.size() || text[i] == ':') {
      parts.push_back(text.substr(start, i - start));
      start = i + 1;
    }
  std::string head = parts.front();
  if (const auto at = head.find('@'); at != std::string::npos) {
    const std::string b = head.substr(at + 1);
    if (b == "cpu") c.backend = Backend::Cpu;
    else if (b == "vulkan") c.backend = Backend::Vulkan;
    else throw Error("configuration '" + text + "': backend '" + b + "' (expected cpu or vulkan)");
    c.hasBackend = true;
    head = head.substr(0, at);
  }
  if (head.empty()) throw Error("configuration '" + text + "': no method (expected method[@backend][:key=value]...)");
  c.method = head;
  for (size_t i = 1; i < parts.size(); ++i) {
    const auto eq = parts[i].find('=');
    if (eq == std::string::npos || eq == 0)
      throw Error("configuration '" + text + "': '" + parts[i] + "' is not key=value (expected method[@backend][:key=value]...)");
    c.settings.emplace_back(parts[i].substr(0, eq), parts[i].substr(eq + 1));
  }
  return c;
}

std::string configText(const RunConfig& c) {
  std::string s = c.method;
  if (c.hasBackend) s += "@" + std::string(backendName(c.backend));
  for (const auto& [k, v] : c.settings) s += ":" + k + "=" + v;
  return s;
}

void checkCompareSettings(const CompareSettings& settings) {
  std::vector<std::string> skipped;
  (void)labelRuns(planRuns(settings, skipped));
}

double MethodRun::medianTotalMs() const { return median(totalMs); }
double MethodRun::medianPassMs(const std::string& pass) const {
  auto it = passMs.find(pass);
  return it == passMs.end() ? std::numeric_limits<double>::quiet_NaN() : median(it->second);
}

FrameSource directorySource(const fs::path& inputDir, const fs::path& referenceDir, int maxFrames) {
  std::shared_ptr<SequenceReader> input = SequenceReader::open(inputDir);
  std::shared_ptr<RgbSequence> reference = RgbSequence::open(referenceDir, "reference");
  const int n = maxFrames > 0 ? std::min(maxFrames, input->frameCount()) : input->frameCount();
  for (int i = 0; i < n; ++i)
    if (reference->indexOf(input->frameNumber(i)) < 0)
      throw Error("reference: no frame " + std::to_string(input->frameNumber(i)) + " in '" + referenceDir.string() +
                  "' for input frame '" + input->framePath(i).string() + "'");
  FrameSource s;
  s.description = "input " + inputDir.string() + ", reference " + referenceDir.string();
  // `rtdenoise render --reference-spp` records the references' sample count in render.json
  // beside them.
  const fs::path referenceAbs = fs::weakly_canonical(referenceDir);
  const fs::path renderJson = referenceAbs.parent_path() / "render.json";
  std::error_code ec;
  if (fs::is_regular_file(renderJson, ec) && fs::file_size(renderJson, ec) < (1u << 20)) {
    std::ifstream in(renderJson);
    const auto j = nlohmann::json::parse(in, nullptr, false);
    if (j.is_object() && j.contains("reference") && j["reference"].is_object() &&
        j["reference"].value("dir", "") == referenceAbs.filename().string() && j["reference"].contains("spp") &&
        j["reference"]["spp"].is_number_integer()) {
      s.referenceSpp = j["reference"]["spp"].get<int>();
      s.referenceNote = "Sample count from " + renderJson.string() + ".";
    }
  }
  s.frameCount = n;
  s.width = input->width();
  s.height = input->height();
  s.load = [input, reference](int index, Image& ref) {
    Frame f = input->read(index);
    const int ri = reference->indexOf(f.number);
    ref = reference->read(ri);
    if (ref.width != f.width || ref.height != f.height)
      throw Error("reference '" + reference->framePath(ri).string() + "' is " + std::to_string(ref.width) + "x" +
                  std::to_string(ref.height) + " but input '" + input->framePath(index).string() + "' is " +
                  std::to_string(f.width) + "x" + std::to_string(f.height));
    return f;
  };
  return s;
}

Comparison runComparison(const FrameSource& source, const CompareSettings& settings,
                         const std::function<void(int, int, const std::string&)>& progress) {
  const auto start = std::chrono::steady_clock::now();
  if (source.frameCount <= 0) throw Error("comparison: the source '" + source.description + "' has no frames");
  Comparison c;
  c.source = source.description;
  c.eval = settings.eval;
  c.frames = source.frameCount;
  c.machine = cpuModel();

  std::vector<Runner> runners;
  if (settings.includeInput) {
    Runner r{{}, nullptr, SequenceEvaluator(settings.eval), {}};
    r.run.label = "input";
    runners.push_back(std::move(r));
  }
  const std::vector<PlannedRun> plan = planRuns(settings, c.skipped);
  const std::vector<std::string> labels = labelRuns(plan);
  std::map<Backend, std::unique_ptr<Device>> devices;
  for (size_t k = 0; k < plan.size(); ++k) {
    const PlannedRun& p = plan[k];
    auto& dev = devices[p.backend];
    if (!dev) {
      DeviceDesc desc;
      desc.backend = p.backend;
      desc.threads = settings.threads;
      if (p.backend == Backend::Vulkan) desc.vulkanDevice = settings.vulkanDevice;
      dev = Device::create(desc);
    }
    Runner r{{}, dev->createDenoiser(p.config.method), SequenceEvaluator(settings.eval), {}};
    applySettings(*r.denoiser, p.settings);
    r.run.method = p.config.method;
    r.run.config = configText(p.config);
    r.run.backend = std::string(backendName(p.backend));
    r.run.label = labels[k];
    r.run.device = dev->name();
    r.run.settings = r.denoiser->settings();
    runners.push_back(std::move(r));
  }

  if (settings.shownFrame >= source.frameCount)
    throw Error("comparison: shown frame index " + std::to_string(settings.shownFrame) + " is past the last of " +
                std::to_string(source.frameCount) + " frames");
  c.shownFrame = settings.shownFrame < 0 ? source.frameCount - 1 : settings.shownFrame;
  double halvesRelMse = 0, halvesPsnr = 0;
  int halvesFrames = 0;
  for (int i = 0; i < source.frameCount; ++i) {
    Image reference;
    const Frame frame = source.load(i, reference);
    if (i == 0) {
      c.width = frame.width;
      c.height = frame.height;
    }
    if (frame.width != c.width || frame.height != c.height)
      throw Error("comparison: frame " + std::to_string(frame.number) + " is " + std::to_string(frame.width) + "x" +
                  std::to_string(frame.height) + ", the first frame was " + std::to_string(c.width) + "x" +
                  std::to_string(c.height));
    c.frameNumbers.push_back(frame.number);
    // The report keeps every frame of every stream, tone-mapped and downscaled by an integer
    // factor to at most reportMaxWidth pixels.
    const int factor = std::max(1, (frame.width + std::max(1, settings.reportMaxWidth) - 1) / std::max(1, settings.reportMaxWidth));
    const auto encode = [&](const Image& img) { return encodeReportImage(img, &c.imageMime); };
    const auto display = [&](const Image& linear) { return encode(toneMap(downscale(linear, factor), settings.eval.toneMap)); };
    c.referenceImages.push_back(display(reference));
    if (source.referenceHalves) {
      Image a, b;
      source.referenceHalves(i, a, b);
      const auto [rel, ps] = referenceNoise(a, b, reference, settings.eval);
      if (i >= settings.eval.warmupFrames) {
        halvesRelMse += rel;
        halvesPsnr += ps;
        ++halvesFrames;
      }
    }
    const FrameInputs inputs = frame.inputs();  // a cut (Frame::cut) resets each denoiser's history
    if (frame.cut)
      for (auto& r : runners) r.evaluator.resetTemporal();  // no temporal error across a cut
    const PreparedReference prepared = prepareReference(frame.number, reference, settings.eval);
    for (auto& r : runners) {
      const Image* result = &frame[Buffer::Color];
      if (r.denoiser) {
        if (r.output.width != frame.width || r.output.height != frame.height) r.output = Image(frame.width, frame.height, 3);
        r.denoiser->denoise(inputs, r.output.view());
        const FrameStats& st = r.denoiser->stats();
        r.run.totalMs.push_back(st.totalMilliseconds);
        if (i >= settings.eval.warmupFrames || source.frameCount <= settings.eval.warmupFrames)
          for (const auto& p : st.passes) {
            if (!r.run.passMs.count(p.name)) r.run.passOrder.push_back(p.name);
            r.run.passMs[p.name].push_back(p.milliseconds);
          }
        result = &r.output;
      }
      Image flipMap;
      r.evaluator.add(*result, prepared, settings.eval.computeFlip ? &flipMap : nullptr);
      r.run.frameImages.push_back(display(*result));
      if (!flipMap.empty()) r.run.flipImages.push_back(encode(colorize(downscale(flipMap, factor))));
    }
    if (progress) progress(i + 1, source.frameCount, "frame " + std::to_string(frame.number));
  }

  for (auto& r : runners) {
    r.run.metrics = {r.run.label, r.evaluator.frames(), r.evaluator.steady(), r.evaluator.warmup()};
    c.runs.push_back(std::move(r.run));
  }
  if (!c.referenceImages.empty()) {
    const int factor = std::max(1, (c.width + std::max(1, settings.reportMaxWidth) - 1) / std::max(1, settings.reportMaxWidth));
    c.displayWidth = (c.width + factor - 1) / factor;
    c.displayHeight = (c.height + factor - 1) / factor;
  }
  c.referenceQuality.spp = source.referenceSpp;
  c.referenceQuality.exact = source.referenceExact;
  c.referenceQuality.note = source.referenceNote;
  if (halvesFrames > 0) {
    c.referenceQuality.estimated = true;
    c.referenceQuality.relMse = halvesRelMse / halvesFrames;
    c.referenceQuality.psnr = halvesPsnr / halvesFrames;
  }
  // Crop: as asked (it must lie inside the image); by default a centred region a third of each side.
  if (settings.cropWidth > 0) {
    if (settings.cropX < 0 || settings.cropY < 0 || settings.cropHeight <= 0 || settings.cropX + settings.cropWidth > c.width ||
        settings.cropY + settings.cropHeight > c.height)
      throw Error("comparison: crop " + std::to_string(settings.cropWidth) + "x" + std::to_string(settings.cropHeight) + " at " +
                  std::to_string(settings.cropX) + "," + std::to_string(settings.cropY) + " does not lie inside the " +
                  std::to_string(c.width) + "x" + std::to_string(c.height) + " image");
    c.cropX = settings.cropX, c.cropY = settings.cropY, c.cropWidth = settings.cropWidth, c.cropHeight = settings.cropHeight;
  } else {
    c.cropWidth = std::max(1, c.width / 3);
    c.cropHeight = std::max(1, c.height / 3);
    c.cropX = (c.width - c.cropWidth) / 2;
    c.cropY = (c.height - c.cropHeight) / 2;
  }
  c.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return c;
}

std::string comparisonTable(const Comparison& c) {
  std::vector<StreamMetrics> streams;
  for (const auto& r : c.runs) streams.push_back(r.metrics);
  std::string out = summaryTable(streams, c.eval);
  for (const auto& note : c.skipped) out += "skipped: " + note + "\n";
  out += "median time per frame (all frames):\n";
  char buf[128];
  for (const auto& r : c.runs) {
    if (r.method.empty()) continue;
    std::snprintf(buf, sizeof buf, "  %-22s %9.2f ms  (%s)\n", r.label.c_str(), r.medianTotalMs(), r.device.c_str());
    out += buf;
  }
  return out;
}

std::string comparisonJson(const Comparison& c) {
  const ReferenceQuality& q = c.referenceQuality;
  nlohmann::json reference = {{"spp", q.spp}, {"exact", q.exact}, {"note", q.note}, {"estimated", q.estimated}};
  if (q.estimated) {
    reference["relMse"] = q.relMse;
    reference["psnr"] = std::isfinite(q.psnr) ? nlohmann::json(q.psnr) : nlohmann::json("inf");
    reference["estimate"] = "from two independent half-sample references A, B: mean (A-B)^2/4 over the frames after warm-up";
  }
  nlohmann::json j = {{"title", c.title},   {"source", c.source},   {"width", c.width},
                      {"height", c.height}, {"frames", c.frames},
                      {"shownFrame", c.frameNumbers.empty() ? 0 : c.frameNumbers[size_t(c.shownFrame)]},
                      {"reference", reference},
                      {"machine", c.machine}, {"seconds", c.seconds}, {"settings", settingsJson(c.eval)},
                      {"skipped", c.skipped}, {"runs", nlohmann::json::array()}};
  for (const auto& r : c.runs) {
    nlohmann::json run = {{"label", r.label},
                          {"config", r.config},
                          {"method", r.method},
                          {"backend", r.backend},
                          {"device", r.device},
                          {"steady", summaryJson(r.metrics.steady)},
                          {"warmup", summaryJson(r.metrics.warmup)},
                          {"frames", framesJson(r.metrics.frames)}};
    if (!r.method.empty()) {
      nlohmann::json settings = nlohmann::json::object(), passes = nlohmann::json::object();
      for (const auto& s : r.settings) settings[s.name] = s.value;
      for (const auto& p : r.passOrder) passes[p] = r.medianPassMs(p);
      run["settings"] = settings;
      run["medianPassMs"] = passes;
      run["medianTotalMs"] = r.medianTotalMs();
      run["totalMs"] = r.totalMs;
    }
    j["runs"].push_back(run);
  }
  return j.dump(1);
}

void writeHtmlReport(const Comparison& c, const fs::path& path) {
  if (path.has_parent_path()) fs::create_directories(path.parent_path());
  writeFileAtomic(path, comparisonHtml(c));
}

}  // namespace rtd::eval
