// Fuzz target: the sequence descriptions. The first byte picks which: even, the input is a
// native sequence.json beside one valid 24x16 frame (frame_0001.exr, written at start-up);
// odd, a Blender cameras.json beside the first frame of the Blender fixture. Opening and
// reading every listed frame (at most four) must give rtd::Error or frames. Seeds:
// fuzz/corpus/sequence_json.
#include "fuzz_util.h"
#include "synthetic/synthetic.h"

using namespace rtd;

namespace {

const fuzz::fs::path& nativeDir() {
  static const fuzz::fs::path dir = [] {
    const fuzz::fs::path d = fuzz::scratchDir("json") / "native";
    synthetic::Scene scene;
    scene.width = 24;
    scene.height = 16;
    SequenceWriter w(d);
    w.write(synthetic::makeFrame(scene, 0));
    return d;
  }();
  return dir;
}

const fuzz::fs::path& blenderDir() {
  static const fuzz::fs::path dir = [] {
    const fuzz::fs::path d = fuzz::scratchDir("json") / "blender";
    fuzz::fs::create_directories(d);
    fuzz::fs::copy_file(fuzz::fs::path(RTD_SOURCE_DIR) / "tests/fixtures/blender/frame_0001.exr", d / "frame_0001.exr");
    return d;
  }();
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const bool blender = data[0] & 1;
  const fuzz::fs::path& dir = blender ? blenderDir() : nativeDir();
  fuzz::writeFile(dir / (blender ? "cameras.json" : "sequence.json"), data + 1, size - 1);
  try {
    auto seq = SequenceReader::open(dir);
    for (int i = 0; i < std::min(seq->frameCount(), 4); ++i) {
      (void)seq->frameNumber(i);
      (void)seq->cutAt(i);
      const Frame f = seq->read(i);
      fuzz::require(f.width == seq->width() && f.height == seq->height(), "frame size differs from the sequence's");
    }
  } catch (const Error&) {
  }
  return 0;
}
