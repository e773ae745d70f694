// rtdenoise denoise: run one method over a sequence directory.
#include <algorithm>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>

#include "cli.h"
#include "denoise_stereo.h"

namespace rtd::cli {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {
void runDenoise(const DenoiseOptions& o) {
  if (isStereoSequence(o.input)) return runDenoiseStereo(o);  // render --stereo output: both eyes
  auto reader = SequenceReader::open(o.input);
  auto device = Device::create({.backend = parseBackend(o.backend), .threads = o.threads, .vulkanDevice = o.vulkanDevice});
  auto denoiser = device->createDenoiser(o.method);
  applySettings(*denoiser, o.settings);

  const auto available = reader->buffers();
  for (Buffer b : denoiser->requiredBuffers())
    if (std::find(available.begin(), available.end(), b) == available.end())
      throw Error("method '" + o.method + "' needs buffer '" + std::string(bufferName(b)) + "', which sequence '" +
                  o.input + "' does not have (first frame: '" + reader->framePath(0).string() + "')");

  fs::create_directories(o.output);
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
                        {"sanitizedValues", st.sanitizedValues}});
    sanitized += st.sanitizedValues;
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
  writeFileAtomic(fs::path(o.output) / "timings.json", timing.dump(1));
  progress.finish();
  if (sanitized)
    std::fprintf(stderr, "note: %llu NaN/Inf/negative radiance values were replaced by 0 (see timings.json)\n",
                 (unsigned long long)sanitized);
  std::printf("wrote %d frames and timings.json to %s\n", frames, o.output.c_str());
}
}  // namespace

void addDenoise(CLI::App& app) {
  auto o = std::make_shared<DenoiseOptions>();
  auto* cmd = app.add_subcommand("denoise", "denoise a sequence (native or Blender multilayer EXR)");
  cmd->add_option("--method,-m", o->method, "method name (see `rtdenoise methods`)")->capture_default_str();
  cmd->add_option("--input,-i", o->input, "sequence directory (a stereo one, with left/ and right/, denoises both eyes)")
      ->required();
  cmd->add_option("--output,-o", o->output, "output directory (frame_NNNN.exr + timings.json; stereo: left/, right/)")
      ->required();
  cmd->add_option("--set,-s", o->settings, "setting as key=value (repeatable)");
  cmd->add_option("--backend,-b", o->backend, "cpu or vulkan")->capture_default_str();
  cmd->add_option("--device", o->vulkanDevice, "Vulkan device index or name substring");
  cmd->add_option("--threads", o->threads, "CPU threads (0 = all)")->capture_default_str();
  cmd->add_option("--frames", o->maxFrames, "denoise only the first N frames (0 = all)");
  cmd->callback([o] { runDenoise(*o); });
}

}  // namespace rtd::cli
