// Reprojection tolerances that do not depend on the scene's units (issue 12): the synthetic
// scene with its geometry and camera scaled by 10 and by 0.1 (world positions, view depths and
// the camera's translation multiplied, motion in pixels unchanged) gives the same history
// decisions as at unit scale for svgf's and bmfr's reprojection defaults, and the same output for
// accumulate and bmfr (bmfr's per-block feature normalization is scale-free once a position
// channel that is constant to rounding, a wall's z = -4 +- 1 ulp, is judged against the
// position's magnitude: judged alone, its square was a column of rounding noise whose pattern
// changed with the scale and the compiler's FMA contraction, 1.4 % of the peak with
// RTD_NATIVE=ON). The absolute form of the position test (BMFR code: 0.04 world units) does
// not, which shows the comparison can tell. Not covered (not scale-free yet, see
// docs/methods/accumulate.md): svgf's a-trous depth weight (depthEpsilon and the cap on its
// denominator are in depth units), and history from the cameras without motion vectors, where
// background pixels' decisions still differ with the scale.
#include <gtest/gtest.h>

#include "core/frame_data.h"
#include "passes/reprojection.h"
#include "rtd/methods/bmfr.h"
#include "rtd/methods/svgf.h"
#include "support/backends.h"
#include "support/convention_frames.h"
#include "support/test_frames.h"

namespace rtd::test {
namespace {

// The frame of a scene whose world is scaled by s about the origin.
void scaleWorld(Frame& f, float s) {
  for (Buffer b : {Buffer::Position, Buffer::Depth})
    for (float& v : f[b].pixels) v *= s;
  for (int r = 0; r < 3; ++r) f.camera.worldToCamera[r * 4 + 3] *= s;  // x_cam = R (s x) + s t
}

ToEngine scaled(float s) {
  return [s](int, Frame& f, FrameConventions&) { scaleWorld(f, s); };
}

synthetic::Scene scene() {
  synthetic::Scene sc;
  sc.width = 64;
  sc.height = 40;
  sc.cameraSpeed = 0.3f;  // fast enough to disocclude the background behind the sphere
  return sc;
}

// History decisions of frame 1 -> 2 at scale s (with the scene's motion vectors).
Reprojection decisions(const ReprojectionSettings& st, float s) {
  const synthetic::Scene sc = scene();
  Frame a = synthetic::makeFrame(sc, 1), b = synthetic::makeFrame(sc, 2);
  for (Frame* f : {&a, &b}) scaleWorld(*f, s);
  const FrameData pa = toFrameData(a), pb = toFrameData(b);
  Reprojection r;
  reproject(pb, &pa, st, r);
  return r;
}

// Number of pixels whose kind differs, and the largest weight difference of the others.
std::pair<size_t, float> compare(const Reprojection& a, const Reprojection& b) {
  size_t differ = 0;
  float dw = 0;
  for (size_t i = 0; i < a.kind.size(); ++i) {
    if (a.kind[i] != b.kind[i] || (a.kind[i] == Reprojection::Bilinear && a.base[i] != b.base[i])) {
      ++differ;
      continue;
    }
    if (a.kind[i] == Reprojection::Bilinear)
      for (int t = 0; t < 4; ++t) dw = std::max(dw, std::abs(a.weights[i][t] - b.weights[i][t]));
  }
  return {differ, dw};
}

TEST(ScaleInvariance, HistoryDecisionsDoNotDependOnTheSceneScale) {
  const ReprojectionSettings svgf = SvgfSettings{}.reprojection, bmfr = BmfrSettings{}.reprojection;
  for (const auto* st : {&svgf, &bmfr}) {
    const Reprojection unit = decisions(*st, 1.0f);
    const auto counts = unit.counts();
    EXPECT_GT(counts[Reprojection::Bilinear], unit.kind.size() * 8 / 10) << "most pixels keep their history";
    EXPECT_GT(counts[Reprojection::None] + counts[Reprojection::Fallback3x3], 0u) << "and some do not (disocclusions)";
    for (float s : {10.0f, 0.1f}) {
      const auto [differ, dw] = compare(unit, decisions(*st, s));
      EXPECT_EQ(differ, 0u) << (st == &svgf ? "svgf" : "bmfr") << " scale " << s;
      EXPECT_LE(dw, 2e-4f);
    }
  }
  // The authors' absolute 0.04: right at one scale, not at the others.
  ReprojectionSettings absolute = bmfr;
  absolute.positionTolerance = 0.04f;
  absolute.positionFootprints = 0.0f;
  const Reprojection unit = decisions(absolute, 1.0f);
  EXPECT_GT(compare(unit, decisions(absolute, 10.0f)).first, unit.kind.size() / 20);
  EXPECT_GT(compare(unit, decisions(absolute, 0.1f)).first, 0u);
}

TEST(ScaleInvariance, OutputsDoNotDependOnTheSceneScale) {
  Device& cpu = *testDevice(Backend::Cpu);
  const synthetic::Scene sc = scene();
  for (const char* method : {"accumulate", "bmfr"}) {
    const auto unit = denoiseSequence(cpu, method, {}, sc, 5, nullptr);
    double peak = 0;
    for (const auto& img : unit)
      for (float v : img.pixels) peak = std::max(peak, double(v));
    for (float s : {10.0f, 0.1f}) {
      const auto other = denoiseSequence(cpu, method, {}, sc, 5, scaled(s));
      // Float rounding of the scaled inputs only: bmfr measured <= 1.3e-6 of the peak at both
      // scales with RTD_NATIVE=ON and OFF (0.023, 1.4 %, before the constant-feature fix, native).
      EXPECT_LE(maxDifference(unit, other), 1e-5 * peak) << method << " at scale " << s;
    }
  }
}

}  // namespace
}  // namespace rtd::test
