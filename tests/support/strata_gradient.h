// A-SVGF's per-stratum gradient G (before its a-trous levels) of a frame with gradient samples,
// through the method's own pass: shared by the method's tests and the renderer's.
#pragma once
#include "methods/asvgf/asvgf_passes.h"
#include "passes/atrous.h"
#include "support/test_frames.h"

namespace rtd::test {

inline asvgf::GradientImage strataGradient(const Frame& f) {
  const FrameData d = toFrameData(f);
  AtrousGuide guide;
  guide.resize(f.width, f.height, 8);
  guide.build(d.plane(Buffer::Depth), d.planes(Buffer::Normal), nullptr, 0.0f);
  asvgf::GradientImage g;
  g.resize(f.width, f.height, 8);
  asvgf::gradientFromSamples(d.plane(Buffer::GradientSample), d.plane(Buffer::GradientPrevious),
                             d.plane(Buffer::GradientCurrent), guide, 1.0f, g);
  return g;
}

}  // namespace rtd::test
