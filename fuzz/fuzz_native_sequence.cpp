// Fuzz target: the native sequence reader on an arbitrary frame file. The input is the bytes of
// frame_0001.exr of a one-frame 24x16 sequence whose sequence.json lists every buffer the
// synthetic scene has; reading it must give an rtd::Error or a frame, which is then denoised.
// Seeds: fuzz/corpus/native_sequence (a synthetic frame).
#include "fuzz_util.h"

using namespace rtd;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const fuzz::fs::path& dir = fuzz::scratchDir("native");
  static const bool manifest = [&] {
    std::ofstream(dir / "sequence.json") << R"({"format": "rtdenoise-sequence", "version": 1, "width": 24, "height": 16,
      "buffers": ["color", "albedo", "normal", "depth", "position", "motion", "objectId", "roughness"],
      "frames": [{"number": 1, "file": "frame_0001.exr"}]})";
    return true;
  }();
  (void)manifest;
  fuzz::writeFile(dir / "frame_0001.exr", data, size);
  try {
    auto seq = SequenceReader::open(dir);
    const Frame f = seq->read(0);
    fuzz::denoiseAndCheck(f, "svgf");
  } catch (const Error&) {
  }
  return 0;
}
