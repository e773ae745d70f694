// Fuzz target: settings by name. The input is text: the first line names a method (by its
// index among the registered ones, the line's first byte modulo their count), each further line
// is key=value as `rtdenoise --set` takes it. Every assignment must be accepted or refused with
// rtd::Error; then two small synthetic frames are denoised on the CPU and the output must be
// finite: no combination of accepted settings may produce NaN or crash. Seeds:
// fuzz/corpus/settings.
#include <sstream>

#include "fuzz_util.h"
#include "synthetic/synthetic.h"

using namespace rtd;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::vector<MethodInfo> methods = listMethods();
  static auto device = Device::create({.backend = Backend::Cpu, .threads = 1});
  static const std::vector<Frame> frames = [] {
    synthetic::Scene scene;
    scene.width = 40;
    scene.height = 24;
    return std::vector<Frame>{synthetic::makeFrame(scene, 0), synthetic::makeFrame(scene, 1)};
  }();
  if (size == 0) return 0;
  const MethodInfo& method = methods[data[0] % methods.size()];
  if (!method.cpu) return 0;
  std::istringstream text(std::string(reinterpret_cast<const char*>(data) + 1, size - 1));
  auto d = device->createDenoiser(method.name);
  std::string line;
  int lines = 0;
  while (std::getline(text, line) && ++lines < 64) {
    const size_t eq = line.find('=');
    if (eq == std::string::npos) continue;
    try {
      d->set(line.substr(0, eq), line.substr(eq + 1));
    } catch (const Error&) {
    }
  }
  Image out(frames[0].width, frames[0].height, 3);
  try {
    for (const Frame& f : frames) {
      d->denoise(f.inputs(), out.view());
      for (float v : out.pixels) fuzz::require(std::isfinite(v), "non-finite output");
    }
  } catch (const Error&) {
  }
  return 0;
}
