// Fuzz target: the Blender importer on an arbitrary multilayer EXR. The input is the bytes of
// frame_0001.exr of a directory without sequence.json; detection, the header and the passes
// must give an rtd::Error or a frame, which is then denoised. Seeds: the Blender fixture
// frames (tests/fixtures/blender).
#include "fuzz_util.h"

using namespace rtd;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const fuzz::fs::path& dir = fuzz::scratchDir("blender");
  fuzz::writeFile(dir / "frame_0001.exr", data, size);
  try {
    auto seq = SequenceReader::open(dir);
    const Frame f = seq->read(0);
    fuzz::denoiseAndCheck(f, "accumulate");
  } catch (const Error&) {
  }
  return 0;
}
