// rtdenoise denoise: run one method over a sequence directory.
#include <algorithm>
#include <filesystem>
#include <map>
#include <tbb/info.h>
#include <nlohmann/json.hpp>

#include "cli.h"
#include "denoise_stereo.h"
#include "io_pipeline.h"
#include "rtd/guide_rays.h"
#include "sanitize_report.h"

namespace rtd::cli {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

/// What `denoise` writes into its output directory (and --overwrite replaces).
const std::vector<std::string> kDenoiseOutputs = {R"(frame_\d+\.(exr|png))", R"(timings\.json)"};

// OpenEXR's pool (rtd::setExrThreads) gets --threads, the CPU device's oneTBB bound (0 = all
// cores); with one thread there is no pool and files are decoded on the reading thread itself.
void setExrThreadsFrom(const DenoiseOptions& o) {
  const int threads = o.device.threads > 0 ? o.device.threads : tbb::info::default_concurrency();
  setExrThreads(threads > 1 ? threads : 0);
}

void runDenoise(const DenoiseOptions& o, const CLI::App& cmd) {
  const auto backend = o.device.single();
  if (!o.preview && (cmd.count("--tonemap") || cmd.count("--exposure")))
    throw UsageError("--tonemap and --exposure shape the PNG previews: give them with --preview");
  eval::ToneMapSettings previewToneMap;
  try {
    previewToneMap.op = eval::parseOperator(o.toneMap);
  } catch (const Error& e) {
    throw UsageError(std::string("--tonemap: ") + e.what());
  }
  previewToneMap.exposure = o.exposure;
  (void)methodInfo(o.method);
  setExrThreadsFrom(o);
  if (isStereoSequence(o.input)) return runDenoiseStereo(o, previewToneMap);  // render --stereo output: both eyes
  auto reader = SequenceReader::open(o.input, o.sequence);
  const int frames = framesToUse(o.maxFrames, reader->frameCount());
  auto device = Device::create(o.device.desc(backend));
  auto denoiser = device->createDenoiser(o.method);
  applySettings(*denoiser, o.settings);

  const auto available = reader->buffers();
  for (Buffer b : denoiser->requiredBuffers())
    if (std::find(available.begin(), available.end(), b) == available.end())
      throw Error("method '" + o.method + "' needs buffer '" + std::string(bufferName(b)) + "', which sequence '" +
                  o.input + "' does not have (first frame: '" + reader->framePath(0).string() + "')");

  // Supersampling with guide rays (Voorhuis Sec. 5) when the sequence carries the samples: the
  // method filters the pre-mixed guide frame (Eq. 7), each sample then takes its guide's colour.
  const int guideSamples = o.noGuideRays ? 0 : reader->guideRaySampleCount();

  o.output.prepare(kDenoiseOutputs);
  const fs::path out(o.output.dir);
  std::fprintf(stderr, "denoising %d frames (%dx%d, %s input%s) with '%s' on %s\n", frames, reader->width(),
               reader->height(), std::string(sequenceKindName(reader->kind())).c_str(),
               guideSamples ? (", " + std::to_string(guideSamples + 1) + " spp with guide rays").c_str() : "",
               o.method.c_str(), device->name().c_str());

  TimingLog log;
  json& timing = log.timing;
  timing["method"] = o.method;
  timing["backend"] = std::string(backendName(device->backend()));
  timing["device"] = device->name();
  timing["input"] = o.input;
  timing["width"] = reader->width();
  timing["height"] = reader->height();
  json settings = json::object();
  for (const auto& s : denoiser->settings()) settings[s.name] = s.value;
  timing["settings"] = settings;
  if (guideSamples) timing["guideRays"] = {{"samplesPerPixel", guideSamples + 1}};

  // Frame i + 1 is read and frame i - 1 written on their own threads while frame i is
  // denoised (io_pipeline.h), unless --no-pipeline.
  struct Input {
    Frame frame;
    GuideRaySamples samples;
  };
  ReadAhead<Input> inputs(frames, o.noPipeline ? 0 : kReadAheadFrames, [&](int i) {
    Input in{reader->read(i), {}};
    if (guideSamples) in.samples = reader->readGuideRaySamples(i);
    return in;
  });
  WriteBehind outputs(o.noPipeline ? 0 : kWriteBehindFrames);
  Progress progress("denoise", frames);
  Image output(reader->width(), reader->height(), 3);
  GuideRays guideRays;  // pre-mix, the method, copy back, on the method's backend (buffers kept)
  try {
    for (int i = 0; i < frames; ++i) {
      const Input in = inputs.next();
      const Frame& frame = in.frame;
      if (guideSamples) output = guideRays.denoise(*denoiser, frame, in.samples);
      else denoiser->denoise(frame.inputs(), output.view());
      char name[32];
      std::snprintf(name, sizeof name, "frame_%04d", frame.number);
      outputs.submit([&o, &previewToneMap, path = out / name, image = output] {
        writeRgbExr(path.string() + ".exr", image, o.half ? ExrPixels::Half : ExrPixels::Float);
        if (o.preview) writeFileAtomic(path.string() + ".png", eval::encodePng(eval::toneMap(image, previewToneMap)));
      });

      FrameStats st = denoiser->stats();
      for (const PassTiming& p : guideRays.passes()) {  // the CPU's, outside the method's stats
        st.passes.push_back(p);
        st.totalMilliseconds += p.milliseconds;
      }
      json passes = json::object();
      for (const auto& p : st.passes) passes[p.name] = p.milliseconds;
      log.add({{"number", frame.number}, {"passes", passes}}, st, frame.cut);
      char detail[64];
      std::snprintf(detail, sizeof detail, "%.1f ms/frame", st.totalMilliseconds);
      progress.update(i + 1, detail);
    }
  } catch (...) {
    outputs.finish();  // a failed write of an earlier frame is the first error
    throw;
  }
  outputs.finish();
  progress.finish();
  log.write(out, o.half);
  std::printf("wrote %d frames and timings.json to %s\n", frames, o.output.dir.c_str());
}
}  // namespace

void addDenoise(CLI::App& app) {
  auto o = std::make_shared<DenoiseOptions>();
  auto* cmd = addSubcommand(app, "denoise", "denoise a sequence (native, per-buffer image files or Blender multilayer EXR)");
  cmd->add_option("--method,-m", o->method, "method name (see `rtdenoise methods`)")->capture_default_str();
  cmd->add_option("--input,-i", o->input, "sequence directory (docs/sequence-format.md); a stereo one (left/, right/) denoises both eyes")->required();
  o->output.add(cmd, "frame_NNNN.exr + timings.json (stereo: left/, right/ + timings.json)");
  cmd->add_option("--set,-s", o->settings, "setting as key=value (repeatable; presets such as variant= apply first)");
  o->device.add(cmd);
  cmd->add_option("--frames", o->maxFrames, "denoise only the first N frames (0 = all)")->capture_default_str();
  cmd->add_option("--cut", o->sequence.cuts,
                  "frame number(s) where the camera cuts: history is reset there (repeatable or comma-separated; "
                  "sequence.json and cameras.json can mark cuts too)")
      ->delimiter(',');
  cmd->add_flag("--continuous", o->sequence.continuous,
                "gaps in the frame numbering are not cuts (by default a gap resets history)");
  cmd->add_flag("--no-guide-rays", o->noGuideRays,
                "ignore a sequence's guide-ray samples (render --guide-rays) and denoise its guide frames alone");
  cmd->add_flag("--no-pipeline", o->noPipeline,
                "read, denoise and write each frame in turn on one thread (by default frame N+1 is read and frame "
                "N-1 written on threads of their own while frame N is denoised; the outputs are the same)");
  cmd->add_flag("--half", o->half, "write half-float EXRs (default 32-bit float)");
  cmd->add_flag("--preview", o->preview, "also write a tone-mapped 8-bit sRGB preview frame_NNNN.png per frame");
  cmd->add_option("--tonemap", o->toneMap, "tone map of the previews: aces, reinhard or clamp")->capture_default_str();
  cmd->add_option("--exposure", o->exposure, "exposure of the previews in stops")->capture_default_str();
  cmd->callback([o, cmd] { runDenoise(*o, *cmd); });
}

}  // namespace rtd::cli
