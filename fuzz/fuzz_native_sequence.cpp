// Fuzz target: the native sequence reader on an arbitrary frame file. The input is the bytes of
// frame_0001.exr of a one-frame 24x16 sequence whose sequence.json lists eight buffers
// (fuzz::writeNativeManifest); reading it must give an rtd::Error or a frame,
// which is then denoised. Seeds: fuzz/corpus/native_sequence (a renderer-made frame).
#include "fuzz_util.h"

using namespace rtd;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const fuzz::fs::path& dir = fuzz::scratchDir("native");
  [[maybe_unused]] static const bool manifest = (fuzz::writeNativeManifest(dir), true);
  if (fuzz::writeInput(fuzz::Target::NativeSequence, dir, data, size)) fuzz::readAndDenoise(dir, "svgf");
  return 0;
}
