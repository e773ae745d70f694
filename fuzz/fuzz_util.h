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
