#include "passes/emitters.h"

#include <atomic>

#include "core/parallel.h"

namespace rtd {

namespace {

// fn(x, y) at every emitter pixel; returns their number.
template <class Fn> size_t forEachEmitter(const FrameData& f, float threshold, Fn&& fn) {
  std::atomic<size_t> count{0};
  const std::vector<Plane>& e = f.planes(Buffer::Emission);
  parallelRows(f.height, [&](int y) {
    const float *r = e[0].row(y), *g = e[1].row(y), *b = e[2].row(y);
    size_t n = 0;
    for (int x = 0; x < f.width; ++x)
      if (emitterPixel(r[x], g[x], b[x], threshold)) {
        fn(x, y);
        ++n;
      }
    if (n) count += n;
  });
  return count;
}

}  // namespace

size_t excludeEmitters(const FrameData& frame, const EmitterSettings& s, AtrousGuide& guide) {
  if (!excludesEmitters(frame, s)) return 0;
  return forEachEmitter(frame, s.emitterThreshold, [&](int x, int y) {
    for (PaddedPlane& n : guide.normal) n.at(x, y) = 0.0f;
  });
}

size_t emitterWeights(const FrameData& frame, const EmitterSettings& s, Plane& weight) {
  weight.resize(frame.width, frame.height, 1.0f);
  return forEachEmitter(frame, s.emitterThreshold, [&](int x, int y) { weight(x, y) = 0.0f; });
}

}  // namespace rtd
