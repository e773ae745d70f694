// Shared pieces of the libFuzzer targets (fuzz/README.md): a scratch directory per process,
// writing the input as a file, and the check every target makes on what it managed to read:
// a frame that a reader accepted is denoised, and the output must be finite.
#pragma once
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "rtd/rtd.h"

namespace rtd::fuzz {

namespace fs = std::filesystem;

/// A directory of this process's own, removed at exit.
inline const fs::path& scratchDir(const char* name) {
  static const fs::path dir = [name] {
    fs::path d = fs::temp_directory_path() / (std::string("rtd_fuzz_") + name + "_" + std::to_string(::getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    std::atexit([] { std::error_code ec; fs::remove_all(scratchDir(""), ec); });
    return d;
  }();
  return dir;
}

inline void writeFile(const fs::path& p, const uint8_t* data, size_t size) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
}

/// The sequence.json of fuzz_native_sequence (and of its regression fixtures): one 24x16 frame,
/// frame_0001.exr, with every buffer the renderer's minimal output has.
inline void writeNativeManifest(const fs::path& dir) {
  std::ofstream(dir / "sequence.json") << R"({"format": "rtdenoise-sequence", "version": 1, "width": 24, "height": 16,
    "buffers": ["color", "albedo", "normal", "depth", "position", "motion", "objectId", "roughness"],
    "frames": [{"number": 1, "file": "frame_0001.exr"}]})";
}

/// The readers the file targets feed, and how each lays its input out in its directory:
/// fuzz_native_sequence's input is frame_0001.exr of a one-frame native sequence (the
/// directory also needs writeNativeManifest), fuzz_blender_sequence's frame_0001.exr of a
/// directory without sequence.json, fuzz_per_buffer's first byte picks the format (modulo
/// kPerBufferExtensions) and the rest is color_0001.<ext>. The regression test
/// (tests/reliability/fuzz_regression_test.cpp) lays its fixtures out the same way.
enum class Target { NativeSequence, BlenderSequence, PerBuffer };
inline constexpr const char* kPerBufferExtensions[] = {"exr", "pfm", "hdr", "png", "tif"};

/// Writes one input into `dir` as `target` reads it; false if the input is too short to be one.
inline bool writeInput(Target target, const fs::path& dir, const uint8_t* data, size_t size) {
  if (target != Target::PerBuffer) {
    writeFile(dir / "frame_0001.exr", data, size);
    return true;
  }
  if (size < 1) return false;
  // One file in the directory at a time: the previous input's file (another format) goes.
  for (const char* ext : kPerBufferExtensions) fs::remove(dir / (std::string("color_0001.") + ext));
  const char* ext = kPerBufferExtensions[data[0] % std::size(kPerBufferExtensions)];
  writeFile(dir / (std::string("color_0001.") + ext), data + 1, size - 1);
  return true;
}

/// Stops the fuzzer (a crash it records) when `ok` is false.
inline void require(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "fuzz check failed: %s\n", what);
    std::abort();
  }
}

/// Denoises a frame a reader accepted (small ones: the point is the values, not the size) with
/// `method` on the CPU and requires a finite output. Errors (rtd::Error) are fine: the frame may
/// lack what the method needs.
inline void denoiseAndCheck(const Frame& f, const char* method) {
  if (f.width > 128 || f.height > 128) return;
  static auto device = Device::create({.backend = Backend::Cpu, .threads = 1});
  try {
    auto d = device->createDenoiser(method);
    Image out(f.width, f.height, 3);
    d->denoise(f.inputs(), out.view());
    for (float v : out.pixels) require(std::isfinite(v), "non-finite output");
  } catch (const Error&) {
  }
}

}  // namespace rtd::fuzz

namespace rtd::fuzz {

/// What each file target does with its input: open the directory's sequence, read its frame
/// and denoise it with `method`; an rtd::Error anywhere is a correct answer to a bad input.
inline void readAndDenoise(const fs::path& dir, const char* method) {
  try {
    auto seq = SequenceReader::open(dir);
    denoiseAndCheck(seq->read(0), method);
  } catch (const Error&) {
  }
}

}  // namespace rtd::fuzz
