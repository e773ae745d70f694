// Fuzz target: the per-buffer image-file reader (docs/sequence-format.md "Per-buffer image
// files") on an arbitrary file. The first input byte picks the format, modulo the list below;
// the rest is the bytes of color_0001.<ext>, alone in a directory. EXR goes through the
// library's OpenEXR reader, the others through the OpenImageIO module (librtdenoise_oiio.so).
// Reading must give an rtd::Error or a frame, which is then denoised. Seeds:
// fuzz/corpus/per_buffer (one small valid file per format, made by fuzz/make_per_buffer_seeds.sh).
#include "fuzz_util.h"

using namespace rtd;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const char* const kExtensions[] = {"exr", "pfm", "hdr", "png", "tif"};
  if (size < 1) return 0;
  const fuzz::fs::path& dir = fuzz::scratchDir("per_buffer");
  // One file in the directory at a time: the previous input's file (another format) goes.
  for (const char* ext : kExtensions) fuzz::fs::remove(dir / (std::string("color_0001.") + ext));
  const char* ext = kExtensions[data[0] % std::size(kExtensions)];
  fuzz::writeFile(dir / (std::string("color_0001.") + ext), data + 1, size - 1);
  try {
    auto seq = SequenceReader::open(dir);
    const Frame f = seq->read(0);
    fuzz::denoiseAndCheck(f, "accumulate");
  } catch (const Error&) {
  }
  return 0;
}
