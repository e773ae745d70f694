// Fuzz target: the per-buffer image-file reader (docs/sequence-format.md "Per-buffer image
// files") on an arbitrary file. The first input byte picks the format (fuzz::writeInput);
// the rest is the bytes of color_0001.<ext>, alone in a directory. EXR goes through the
// library's OpenEXR reader, the others through the OpenImageIO module (librtdenoise_oiio.so).
// Reading must give an rtd::Error or a frame, which is then denoised. Seeds:
// fuzz/corpus/per_buffer (one small valid file per format, made by fuzz/make_per_buffer_seeds.sh).
#include "fuzz_util.h"

using namespace rtd;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const fuzz::fs::path& dir = fuzz::scratchDir("per_buffer");
  if (fuzz::writeInput(fuzz::Target::PerBuffer, dir, data, size)) fuzz::readAndDenoise(dir, "accumulate");
  return 0;
}
