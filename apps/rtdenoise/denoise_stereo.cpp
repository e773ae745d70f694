#include "denoise_stereo.h"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "cli.h"
#include "io_pipeline.h"
#include "sanitize_report.h"

namespace rtd::cli {

namespace fs = std::filesystem;
using nlohmann::json;

bool isStereoSequence(const fs::path& dir) {
  return !fs::exists(dir / "sequence.json") && fs::is_directory(dir / "left") && fs::is_directory(dir / "right");
}

/// What a stereo `denoise` writes into its output directory (and --overwrite replaces).
const std::vector<std::string> kStereoOutputs = {"left", "right", R"(timings\.json)"};

void runDenoiseStereo(const DenoiseOptions& o, const eval::ToneMapSettings& previewToneMap) {
  const fs::path in(o.input), out(o.output.dir);
  std::unique_ptr<SequenceReader> eyes[2] = {SequenceReader::open(in / "left", o.sequence),
                                             SequenceReader::open(in / "right", o.sequence)};
  const char* names[2] = {"left", "right"};
  const SequenceReader &l = *eyes[0], &r = *eyes[1];
  if (l.width() != r.width() || l.height() != r.height())
    throw Error("stereo sequence '" + o.input + "': the left eye is " + std::to_string(l.width()) + "x" +
                std::to_string(l.height()) + ", the right eye " + std::to_string(r.width()) + "x" + std::to_string(r.height()));
  if (l.frameCount() != r.frameCount())
    throw Error("stereo sequence '" + o.input + "': the left eye has " + std::to_string(l.frameCount()) +
                " frames, the right eye " + std::to_string(r.frameCount()));
  for (int i = 0; i < l.frameCount(); ++i)
    if (l.frameNumber(i) != r.frameNumber(i))
      throw Error("stereo sequence '" + o.input + "': frame " + std::to_string(i + 1) + " is number " +
                  std::to_string(l.frameNumber(i)) + " on the left and " + std::to_string(r.frameNumber(i)) + " on the right");

  for (int e = 0; e < 2; ++e)
    if (eyes[e]->guideRaySampleCount() > 0 && !o.noGuideRays)
      throw Error("stereo sequence '" + o.input + "': the " + names[e] +
                  " eye carries guide-ray samples, which stereo denoising does not use (--no-guide-rays denoises "
                  "the guide frames alone)");

  const int frames = framesToUse(o.maxFrames, l.frameCount());
  auto device = Device::create(o.device.desc(o.device.single()));
  auto denoiser = device->createStereoDenoiser(o.method);
  applySettings(*denoiser, o.settings);
  for (int e = 0; e < 2; ++e) {
    const auto available = eyes[e]->buffers();
    for (Buffer b : denoiser->requiredBuffers())
      if (std::find(available.begin(), available.end(), b) == available.end())
        throw Error("method '" + o.method + "' needs buffer '" + std::string(bufferName(b)) + "', which the " + names[e] +
                    " eye of '" + o.input + "' does not have (first frame: '" + eyes[e]->framePath(0).string() + "')");
  }

  o.output.prepare(kStereoOutputs);
  for (const char* e : names) fs::create_directories(out / e);
  std::fprintf(stderr, "denoising %d stereo frames (2 x %dx%d) with '%s' on %s\n", frames, l.width(), l.height(),
               o.method.c_str(), device->name().c_str());

  TimingLog log;
  json& timing = log.timing;
  timing["method"] = o.method;
  timing["stereo"] = true;
  timing["backend"] = std::string(backendName(device->backend()));
  timing["device"] = device->name();
  timing["input"] = o.input;
  timing["width"] = l.width();
  timing["height"] = l.height();
  json settings = json::object();
  for (const auto& s : denoiser->settings()) settings[s.name] = s.value;
  timing["settings"] = settings;
  // Both eyes of frame i + 1 are read and those of frame i - 1 written on their own threads
  // while frame i is denoised (io_pipeline.h), unless --no-pipeline.
  ReadAhead<std::pair<Frame, Frame>> inputs(frames, o.noPipeline ? 0 : kReadAheadFrames,
                                            [&](int i) { return std::pair{l.read(i), r.read(i)}; });
  WriteBehind writes(o.noPipeline ? 0 : kWriteBehindFrames);
  Progress progress("denoise", frames);
  Image outputs[2] = {Image(l.width(), l.height(), 3), Image(l.width(), l.height(), 3)};
  try {
    for (int i = 0; i < frames; ++i) {
      const auto [fl, fr] = inputs.next();
      StereoFrameInputs stereo;
      stereo.eye[0] = fl.inputs();
      stereo.eye[1] = fr.inputs();
      denoiser->denoise(stereo, outputs[0].view(), outputs[1].view());
      char name[32];
      std::snprintf(name, sizeof name, "frame_%04d", fl.number);
      writes.submit([&o, &previewToneMap, &out, &names, name = std::string(name), left = outputs[0], right = outputs[1]] {
        const Image* images[2] = {&left, &right};
        for (int e = 0; e < 2; ++e) {
          const fs::path path = out / names[e] / name;
          writeRgbExr(path.string() + ".exr", *images[e], o.half ? ExrPixels::Half : ExrPixels::Float);
          if (o.preview) writeFileAtomic(path.string() + ".png", eval::encodePng(eval::toneMap(*images[e], previewToneMap)));
        }
      });
      const FrameStats& st = denoiser->stats();
      json passes = json::object();
      for (const auto& p : st.passes) passes[p.name] = p.milliseconds;
      json memory = json::object();
      for (const auto& m : st.memory) memory[m.category] = m.bytes;
      log.add({{"number", fl.number},
               {"passes", passes},
               {"eyeTotalMs", {denoiser->eyeStats(0).totalMilliseconds, denoiser->eyeStats(1).totalMilliseconds}},
               {"memoryBytes", memory}},
              st, fl.cut || fr.cut);
      char detail[64];
      std::snprintf(detail, sizeof detail, "%.1f ms/frame (both eyes)", st.totalMilliseconds);
      progress.update(i + 1, detail);
    }
  } catch (...) {
    writes.finish();  // a failed write of an earlier frame is the first error
    throw;
  }
  writes.finish();
  progress.finish();
  log.write(out, o.half);
  std::printf("wrote %d frames per eye to %s/left and %s/right, and timings.json\n", frames, o.output.dir.c_str(),
              o.output.dir.c_str());
}

}  // namespace rtd::cli
