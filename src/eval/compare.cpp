// Running several methods on one sequence and evaluating them side by side.
#include <algorithm>
#include <chrono>
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

/// Applies "method.key=value" or "key=value" assignments that concern this denoiser.
void applySettings(Denoiser& d, const std::vector<std::string>& assignments) {
  const auto known = d.settings();
  for (const auto& a : assignments) {
    const auto eq = a.find('=');
    if (eq == std::string::npos || eq == 0) throw Error("setting '" + a + "': expected method.key=value or key=value");
    std::string key = a.substr(0, eq);
    const std::string value = a.substr(eq + 1);
    const auto dot = key.find('.');
    if (dot != std::string::npos && key.substr(0, dot) == d.method()) {
      key = key.substr(dot + 1);
    } else if (dot != std::string::npos) {
      // Either another method's setting, or a dotted setting name of this method.
      bool mine = false;
      for (const auto& s : known) mine |= s.name == key;
      if (!mine) continue;
    } else {
      bool has = false;
      for (const auto& s : known) has |= s.name == key;
      if (!has) continue;
    }
    d.set(key, value);
  }
}

struct Runner {
  MethodRun run;
  std::unique_ptr<Denoiser> denoiser;  // null for the input
  SequenceEvaluator evaluator;
  Image output;
};
}  // namespace

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
  s.frameCount = n;
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
  std::vector<std::string> methods = settings.methods;
  if (methods.empty())
    for (const auto& m : listMethods())
      if (m.cpu) methods.push_back(m.name);

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
  std::map<Backend, std::unique_ptr<Device>> devices;
  for (Backend b : settings.backends) {
    auto& dev = devices[b];
    if (!dev) {
      DeviceDesc desc;
      desc.backend = b;
      desc.threads = settings.threads;
      dev = Device::create(desc);
    }
    for (const auto& m : methods) {
      // A method without an implementation on this backend is skipped (and noted) when another
      // backend runs it, so `--backends cpu,vulkan` compares what exists on both.
      const auto infos = listMethods();
      const auto info = std::find_if(infos.begin(), infos.end(), [&](const MethodInfo& i) { return i.name == m; });
      if (info != infos.end() && settings.backends.size() > 1 && !(b == Backend::Cpu ? info->cpu : info->vulkan)) {
        c.skipped.push_back(m + " on " + std::string(backendName(b)) + ": not implemented on this backend");
        continue;
      }
      Runner r{{}, dev->createDenoiser(m), SequenceEvaluator(settings.eval), {}};
      applySettings(*r.denoiser, settings.settings);
      r.run.method = m;
      r.run.backend = std::string(backendName(b));
      r.run.label = settings.backends.size() > 1 ? m + " (" + r.run.backend + ")" : m;
      r.run.device = dev->name();
      r.run.settings = r.denoiser->settings();
      runners.push_back(std::move(r));
    }
  }

  const int shown = settings.shownFrame < 0 ? source.frameCount - 1 : std::min(settings.shownFrame, source.frameCount - 1);
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
    const bool isShown = i == shown;
    if (isShown) {
      c.reference = reference;
      c.shownFrameNumber = frame.number;
    }
    const FrameInputs inputs = frame.inputs();
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
      const FrameMetrics& m = r.evaluator.add(*result, prepared, isShown ? &r.run.flipMap : nullptr);
      if (isShown) {
        r.run.shown = *result;
        r.run.shownFlip = m.flip;
      }
    }
    if (progress) progress(i + 1, source.frameCount, "frame " + std::to_string(frame.number));
  }

  for (auto& r : runners) {
    r.run.metrics = {r.run.label, r.evaluator.frames(), r.evaluator.steady(), r.evaluator.warmup()};
    c.runs.push_back(std::move(r.run));
  }
  // Crop: as asked, clamped to the image; by default a centred region a third of each side.
  c.cropWidth = settings.cropWidth > 0 ? std::min(settings.cropWidth, c.width) : std::max(1, std::min(c.width, c.width / 3));
  c.cropHeight = settings.cropHeight > 0 ? std::min(settings.cropHeight, c.height) : std::max(1, std::min(c.height, c.height / 3));
  c.cropX = settings.cropWidth > 0 ? std::clamp(settings.cropX, 0, c.width - c.cropWidth) : (c.width - c.cropWidth) / 2;
  c.cropY = settings.cropWidth > 0 ? std::clamp(settings.cropY, 0, c.height - c.cropHeight) : (c.height - c.cropHeight) / 2;
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
  nlohmann::json j = {{"title", c.title},   {"source", c.source},   {"width", c.width},
                      {"height", c.height}, {"frames", c.frames},   {"shownFrame", c.shownFrameNumber},
                      {"machine", c.machine}, {"seconds", c.seconds}, {"settings", settingsJson(c.eval)},
                      {"skipped", c.skipped}, {"runs", nlohmann::json::array()}};
  for (const auto& r : c.runs) {
    nlohmann::json run = {{"label", r.label},
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
