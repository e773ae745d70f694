// accumulateRow(), the three-plane accumulation added to the shared passes for BMFR's phase
// III, against its definition per plane through Reprojection::gather().
#include <gtest/gtest.h>

#include <random>

#include "passes/reprojection.h"
#include "passes/temporal_accumulation.h"
#include "support/test_frames.h"
#include "synthetic/synthetic.h"

namespace rtd {
namespace {

TEST(BmfrPasses, AccumulateRowEqualsItsDefinitionPerPlane) {
  synthetic::Scene scene;
  scene.width = 96;
  scene.height = 64;
  scene.cameraSpeed = 0.1f;  // a few disocclusions (None) besides bilinear taps
  const FrameData previous = test::toFrameData(synthetic::makeFrame(scene, 0));
  const FrameData current = test::toFrameData(synthetic::makeFrame(scene, 1));
  for (bool fallback : {false, true}) {
    ReprojectionSettings settings;
    settings.fallback3x3 = fallback;
    Reprojection rp;
    reproject(current, &previous, settings, rp);
    const auto kinds = rp.counts();
    EXPECT_GT(kinds[Reprojection::Bilinear], 0u);
    Plane length(96, 64);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.0f, 4.0f);
    for (auto& v : length.data) v = std::round(u(rng)) + 1.0f;
    Plane3 cur, hist, joint, single;
    for (auto* p : {&cur, &hist, &joint, &single}) resize(*p, 96, 64);
    for (int c = 0; c < 3; ++c)
      for (size_t i = 0; i < cur[c].size(); ++i) {
        cur[c].data[i] = u(rng);
        hist[c].data[i] = u(rng);
      }
    for (int y = 0; y < 64; ++y) {
      const float* row[3] = {cur[0].row(y), cur[1].row(y), cur[2].row(y)};
      accumulateRow(rp, length, 0.1f, row, hist, joint, y);
    }
    for (int c = 0; c < 3; ++c)
      for (size_t i = 0; i < cur[c].size(); ++i) {
        const float a = newSampleWeight(length.data[i], 0.1f);
        single[c].data[i] = rp.kind[i] == Reprojection::None ? cur[c].data[i]
                                                             : a * cur[c].data[i] + (1.0f - a) * rp.gather(hist[c], i);
      }
    for (int c = 0; c < 3; ++c)
      for (size_t i = 0; i < cur[c].size(); ++i) ASSERT_FLOAT_EQ(joint[c].data[i], single[c].data[i]) << i;
  }
}

}  // namespace
}  // namespace rtd
