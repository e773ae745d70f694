// Fuzz target: the Blender importer on an arbitrary multilayer EXR. The input is the bytes of
// frame_0001.exr of a directory without sequence.json; detection, the header and the passes
// must give an rtd::Error or a frame, which is then denoised. Seeds: the Blender fixture
// frames (tests/fixtures/blender).
#include "fuzz_util.h"

using namespace rtd;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const fuzz::fs::path& dir = fuzz::scratchDir("blender");
  if (fuzz::writeInput(fuzz::Target::BlenderSequence, dir, data, size)) fuzz::readAndDenoise(dir, "accumulate");
  return 0;
}
