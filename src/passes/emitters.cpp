#include "passes/emitters.h"

#include <atomic>

#include "core/parallel.h"

namespace rtd {

namespace {

// fn(x, y) at every emitter pixel, and with `albedo` only where it also has no reflectance
// (reflectanceless()); returns their number.
template <class Fn> size_t forEachEmitter(const FrameData& f, float threshold, const std::vector<Plane>* albedo, Fn&& fn) {
  std::atomic<size_t> count{0};
  const std::vector<Plane>& e = f.planes(Buffer::Emission);
  parallelRows(f.height, [&](int y) {
    const float *r = e[0].row(y), *g = e[1].row(y), *b = e[2].row(y);
    const float* a[3] = {nullptr, nullptr, nullptr};
    if (albedo)
      for (int c = 0; c < 3; ++c) a[c] = (*albedo)[c].row(y);
    size_t n = 0;
    for (int x = 0; x < f.width; ++x)
      if (emitterPixel(r[x], g[x], b[x], threshold) && (!albedo || reflectanceless(a[0][x], a[1][x], a[2][x]))) {
        fn(x, y);
        ++n;
      }
    if (n) count += n;
  });
  return count;
}

}  // namespace

size_t excludeEmitters(const FrameData& frame, const EmitterSettings& s, AtrousGuide& guide) {
  if (!frame.has(Buffer::Emission)) return 0;
  // Off, only the emitters without a reflectance (Cycles' pure emitters) leave the filter.
  const bool all = s.excludeEmitters;
  if (!all && !frame.has(Buffer::Albedo)) return 0;
  const std::vector<Plane>* albedo = all ? nullptr : &frame.planes(Buffer::Albedo);
  return forEachEmitter(frame, s.emitterThreshold, albedo, [&](int x, int y) {
    for (PaddedPlane& n : guide.normal) n.at(x, y) = 0.0f;
  });
}

size_t emitterWeights(const FrameData& frame, const EmitterSettings& s, Plane& weight) {
  weight.resize(frame.width, frame.height, 1.0f);
  return forEachEmitter(frame, s.emitterThreshold, nullptr, [&](int x, int y) { weight(x, y) = 0.0f; });
}

}  // namespace rtd
