// rtdenoise pack: any sequence rtdenoise reads (per-buffer image files, Blender multilayer EXR,
// native) -> a native sequence with its sequence.json, and a list of what is missing.
#include <algorithm>
#include <filesystem>

#include "cli.h"

namespace rtd::cli {

namespace fs = std::filesystem;

namespace {
struct PackOptions {
  std::string input;
  OutputOptions output;
  int frames = 0;
};

const std::vector<std::string> kPackOutputs = {R"(frame_\d+\.exr)", R"(sequence\.json)"};

/// What the methods need that the sequence lacks, one line per missing buffer.
std::string missingReport(const SequenceReader& reader) {
  const auto present = reader.buffers();
  std::string out;
  auto device = Device::create({.backend = Backend::Cpu, .threads = 1});
  for (const Buffer b : {Buffer::Albedo, Buffer::Normal, Buffer::Depth, Buffer::Motion, Buffer::Position, Buffer::ObjectId}) {
    if (std::find(present.begin(), present.end(), b) != present.end()) continue;
    std::string needers;
    for (const auto& m : listMethods()) {
      const auto required = device->createDenoiser(m.name)->requiredBuffers();
      if (std::find(required.begin(), required.end(), b) != required.end()) needers += (needers.empty() ? "" : ", ") + m.name;
    }
    out += "  missing " + std::string(bufferName(b)) +
           (needers.empty() ? std::string(" (no method requires it)") : " (required by " + needers + ")") + "\n";
  }
  return out;
}

void runPack(const PackOptions& o) {
  auto reader = SequenceReader::open(o.input);
  const int frames = framesToUse(o.frames, reader->frameCount());
  o.output.prepare(kPackOutputs);
  SequenceWriter writer(o.output.dir);
  Progress progress("pack", frames);
  int cameras = 0;
  for (int i = 0; i < frames; ++i) {
    const Frame f = reader->read(i);
    cameras += f.camera.valid;
    writer.write(f);
    progress.update(i + 1);
  }
  writer.finish();
  progress.finish();
  std::string names;
  for (Buffer b : reader->buffers()) names += (names.empty() ? "" : ", ") + std::string(bufferName(b));
  std::printf("packed %d frame(s) of %dx%d into %s\n  buffers: %s\n%s  cameras: %s\n", frames, reader->width(),
              reader->height(), (fs::path(o.output.dir) / "sequence.json").string().c_str(), names.c_str(),
              missingReport(*reader).c_str(),
              cameras == frames ? "every frame"
              : cameras == 0    ? "none (no camera file; methods reproject with motion only)"
                                : (std::to_string(cameras) + " of " + std::to_string(frames) + " frames").c_str());
}
}  // namespace

void addPack(CLI::App& app) {
  auto o = std::make_shared<PackOptions>();
  auto* cmd = addSubcommand(app, "pack",
                            "convert a sequence (per-buffer image files, Blender multilayer EXR) into a native sequence "
                            "and list what is missing");
  cmd->add_option("--input,-i", o->input, "sequence directory (docs/sequence-format.md)")->required();
  o->output.add(cmd, "the native sequence (frame_NNNN.exr + sequence.json)");
  cmd->add_option("--frames", o->frames, "only the first N frames (0 = all)")->capture_default_str();
  cmd->callback([o] { runPack(*o); });
}

}  // namespace rtd::cli
