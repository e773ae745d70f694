// rtdenoise denoise: run one method over a sequence directory.
#include <algorithm>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>

#include "cli.h"
#include "sanitize_report.h"

namespace rtd::cli {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {
struct DenoiseOptions {
  std::string method = "svgf";
  std::string input, output;
  std::vector<std::string> settings;
  std::string backend = "cpu";
  std::string vulkanDevice;
  int threads = 0;
  int maxFrames = 0;
  SequenceOptions sequence;  // --cut, --continuous
};

void runDenoise(const DenoiseOptions& o) {
  auto reader = SequenceReader::open(o.input, o.sequence);
  auto device = Device::create({.backend = parseBackend(o.backend), .threads = o.threads, .vulkanDevice = o.vulkanDevice});
  auto denoiser = device->createDenoiser(o.method);
  applySettings(*denoiser, o.settings);

  const auto available = reader->buffers();
  for (Buffer b : denoiser->requiredBuffers())
    if (std::find(available.begin(), available.end(), b) == available.end())
      throw Error("method '" + o.method + "' needs buffer '" + std::string(bufferName(b)) + "', which sequence '" +
                  o.input + "' does not have (first frame: '" + reader->framePath(0).string() + "')");

  fs::create_directories(o.output);
  removeStaleTemporaryFiles(o.output);
  const int frames = o.maxFrames > 0 ? std::min(o.maxFrames, reader->frameCount()) : reader->frameCount();
  std::fprintf(stderr, "denoising %d frames (%dx%d, %s input) with '%s' on %s\n", frames, reader->width(),
               reader->height(), reader->kind() == SequenceKind::Native ? "native" : "Blender", o.method.c_str(),
               device->name().c_str());

  json timing;
  timing["method"] = o.method;
  timing["backend"] = std::string(backendName(device->backend()));
  timing["device"] = device->name();
  timing["input"] = o.input;
  timing["width"] = reader->width();
  timing["height"] = reader->height();
  json settings = json::object();
  for (const auto& s : denoiser->settings()) settings[s.name] = s.value;
  timing["settings"] = settings;
  json perFrame = json::array();
  uint64_t sanitized = 0;
  BufferCounts sanitizedPerBuffer{};
  std::vector<double> totals;

  Progress progress("denoise", frames);
  Image output(reader->width(), reader->height(), 3);
  for (int i = 0; i < frames; ++i) {
    const Frame frame = reader->read(i);
    denoiser->denoise(frame.inputs(), output.view());
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.exr", frame.number);
    writeRgbExr(fs::path(o.output) / name, output);

    const FrameStats& st = denoiser->stats();
    json passes = json::object();
    for (const auto& p : st.passes) passes[p.name] = p.milliseconds;
    perFrame.push_back({{"number", frame.number}, {"passes", passes}, {"totalMs", st.totalMilliseconds},
                        {"sanitizedValues", st.sanitizedValues}, {"sanitized", sanitizeJson(st.sanitized)}});
    if (frame.cut) perFrame.back()["cut"] = true;
    sanitized += st.sanitizedValues;
    accumulate(sanitizedPerBuffer, st.sanitized);
    totals.push_back(st.totalMilliseconds);
    char detail[64];
    std::snprintf(detail, sizeof detail, "%.1f ms/frame", st.totalMilliseconds);
    progress.update(i + 1, detail);
  }
  std::vector<double> sorted = totals;
  std::sort(sorted.begin(), sorted.end());
  timing["frames"] = perFrame;
  timing["medianTotalMs"] = sorted.empty() ? 0.0 : sorted[sorted.size() / 2];
  timing["sanitizedValues"] = sanitized;
  timing["sanitized"] = sanitizeJson(sanitizedPerBuffer);
  writeFileAtomic(fs::path(o.output) / "timings.json", timing.dump(1));
  progress.finish();
  if (sanitized)
    std::fprintf(stderr, "note: %llu input values were sanitized: %s (see timings.json)\n", (unsigned long long)sanitized,
                 sanitizeSummary(sanitizedPerBuffer).c_str());
  std::printf("wrote %d frames and timings.json to %s\n", frames, o.output.c_str());
}
}  // namespace

void addDenoise(CLI::App& app) {
  auto o = std::make_shared<DenoiseOptions>();
  auto* cmd = app.add_subcommand("denoise", "denoise a sequence (native or Blender multilayer EXR)");
  cmd->add_option("--method,-m", o->method, "method name (see `rtdenoise methods`)")->capture_default_str();
  cmd->add_option("--input,-i", o->input, "sequence directory")->required();
  cmd->add_option("--output,-o", o->output, "output directory (frame_NNNN.exr + timings.json)")->required();
  cmd->add_option("--set,-s", o->settings, "setting as key=value (repeatable)");
  cmd->add_option("--backend,-b", o->backend, "cpu or vulkan")->capture_default_str();
  cmd->add_option("--device", o->vulkanDevice, "Vulkan device index or name substring");
  cmd->add_option("--threads", o->threads, "CPU threads (0 = all)")->capture_default_str();
  cmd->add_option("--frames", o->maxFrames, "denoise only the first N frames (0 = all)");
  cmd->add_option("--cut", o->sequence.cuts,
                  "frame number(s) where the camera cuts: history is reset there (repeatable or comma-separated; "
                  "sequence.json and cameras.json can mark cuts too)")
      ->delimiter(',');
  cmd->add_flag("--continuous", o->sequence.continuous,
                "gaps in the frame numbering are not cuts (by default a gap resets history)");
  cmd->callback([o] { runDenoise(*o); });
}

}  // namespace rtd::cli
