// Emitter halo (issue 12 item 3) on Blender Cycles input, where it was reported:
// tests/fixtures/blender_lamp (tools/blender/make_lamp_fixture.py), a Cornell-like room whose
// lamp is an emissive mesh plane 2 mm below the ceiling with the default pass index 0, still
// camera, a slowly moving cube, 96x54, 12 frames at 1 spp with the Emit pass, a 2048-spp
// reference of the same (centre-sampled) pixels. After the 12 frames, the mean |error| of
// display luma (Reinhard, sRGB) of the ceiling pixels 1 to 3 pixels from the lamp is compared
// with that of the ceiling 6 or more pixels away.
//
// Measured (docs/methods/svgf.md and bmfr.md, "Emitters"): bmfr (excludeEmitters on, its
// default) 0.0143 next to the lamp vs 0.0139 elsewhere (ratio 1.03); off, or with the old
// settings (positionTolerance 0.04, no footprints), 0.0255 vs 0.0140 (1.82). svgf with the
// lamp out of the filter (now its default here, or excludeEmitters=true) 0.0300 vs 0.0103
// (2.91), with the lamp in it (before: excludeEmitters off and no albedo rule) 0.0436 vs 0.0110
// (3.96), the same with the old absolute depth epsilon; Dundr 0.0247 vs 0.0094 (2.62) / 0.0343
// vs 0.0102 (3.36). The cause the exclusion removes: Cycles' Denoising Albedo of an emissive
// surface is its emission (12 here) and its non-emissive radiance is 0, so in the filter the
// lamp's pixels are black (demodulated 0) neighbours of the ceiling and take the ceiling's light
// times 12 themselves. What remains for svgf is not the lamp: one a-trous level gives 0.0186
// (1.62), TAA off 0.0263 (2.40): the a-trous levels flatten the ceiling's illumination, which
// peaks around the lamp, and TAA's clamp box still reads the lamp's pixels.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "passes/tonemap.h"
#include "rtd/rtd.h"
#ifdef HAVE_RTDENOISE_EVAL
#include "rtd/eval/evaluate.h"
#endif

namespace rtd {
namespace {

#ifdef HAVE_RTDENOISE_EVAL
const std::filesystem::path kLamp = std::filesystem::path(RTD_SOURCE_DIR) / "tests/fixtures/blender_lamp";

double displayLuma(const Image& img, int x, int y) {
  auto d = [&](int c) { return tonemap::toneMapToSrgb(img.at(x, y, c), tonemap::Operator::Reinhard, 1.0f); };
  return tonemap::luminance(d(0), d(1), d(2));
}

struct Halo {
  double near = 0, far = 0, nearBias = 0, farBias = 0;
  double ratio() const { return near / far; }
};

class BlenderLamp : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    seq_ = SequenceReader::open(kLamp).release();
    ref_ = eval::RgbSequence::open(kLamp / "reference", "reference").release();
  }
  static void TearDownTestSuite() {
    delete seq_;
    delete ref_;
  }

  // The ceiling's halo measure of `method` with `settings` after every frame of the fixture.
  static Halo measure(const std::string& method, const std::vector<std::pair<std::string, std::string>>& settings) {
    auto d = Device::create({.backend = Backend::Cpu, .threads = 2})->createDenoiser(method);
    for (const auto& [k, v] : settings) d->set(k, v);
    Frame last;
    Image out;
    for (int i = 0; i < seq_->frameCount(); ++i) {
      last = seq_->read(i);
      out = Image(last.width, last.height, 3);
      d->denoise(last.inputs(), out.view());
    }
    const Image reference = ref_->read(ref_->indexOf(last.number));
    const int w = last.width, h = last.height;
    // The lamp: its emission (the frames are centre-sampled: the same pixels every frame). The
    // ceiling: downward normal at the ceiling's height (2.8 m, Blender's z up; the lamp is at
    // 2.798 m), the lamp's pixels left out.
    auto emitter = [&](int x, int y) { return last[Buffer::Emission].at(x, y, 0) > 0.0f; };
    auto ceiling = [&](int x, int y) {
      return last[Buffer::Normal].at(x, y, 2) < -0.9f && last[Buffer::Position].at(x, y, 2) > 2.79f && !emitter(x, y);
    };
    auto distance = [&](int x, int y) {  // Chebyshev distance to the nearest emitter pixel, capped
      for (int r = 1; r <= 8; ++r)
        for (int dy = -r; dy <= r; ++dy)
          for (int dx = -r; dx <= r; ++dx) {
            const int qx = x + dx, qy = y + dy;
            if (qx >= 0 && qy >= 0 && qx < w && qy < h && emitter(qx, qy)) return r;
          }
      return 9;
    };
    int lamp = 0, nNear = 0, nFar = 0;
    Halo r;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        lamp += emitter(x, y);
        if (!ceiling(x, y)) continue;
        const int dist = distance(x, y);
        const double e = displayLuma(out, x, y) - displayLuma(reference, x, y);
        if (dist <= 3) r.near += std::abs(e), r.nearBias += e, ++nNear;
        if (dist >= 6) r.far += std::abs(e), r.farBias += e, ++nFar;
      }
    EXPECT_GE(lamp, 40) << "the lamp is visible";
    EXPECT_GT(nNear, 100);
    EXPECT_GT(nFar, 300);
    r.near /= nNear, r.far /= nFar, r.nearBias /= nNear, r.farBias /= nFar;
    std::string name = method;
    for (const auto& [k, v] : settings) name += " " + k + "=" + v;
    std::printf("%s: ceiling next to the lamp |err| %.4f (bias %+.4f, %d px), elsewhere %.4f (bias %+.4f, %d px), ratio %.2f\n",
                name.c_str(), r.near, r.nearBias, nNear, r.far, r.farBias, nFar, r.ratio());
    return r;
  }

  static SequenceReader* seq_;
  static eval::RgbSequence* ref_;
};
SequenceReader* BlenderLamp::seq_ = nullptr;
eval::RgbSequence* BlenderLamp::ref_ = nullptr;

TEST_F(BlenderLamp, TheSequenceHasTheLampAsEmission) {
  const auto buffers = seq_->buffers();
  for (Buffer b : {Buffer::Emission, Buffer::Albedo, Buffer::Normal, Buffer::Position, Buffer::Motion})
    EXPECT_NE(std::find(buffers.begin(), buffers.end(), b), buffers.end()) << bufferName(b);
  EXPECT_EQ(seq_->frameCount(), 12);
  EXPECT_EQ(ref_->frameCount(), 12);
}

// BMFR with its default exclusion: no halo (the error next to the lamp within 1.3x the error
// elsewhere on the ceiling; 1.03 measured). With the old cause present (exclusion off: the lamp
// enters its blocks' fits as a black surface) the same bound fails (1.82).
TEST_F(BlenderLamp, BmfrCeilingNextToTheLampIsLikeElsewhere) {
  const Halo on = measure("bmfr", {});
  EXPECT_LT(on.ratio(), 1.3);
  const Halo off = measure("bmfr", {{"excludeEmitters", "false"}});
  EXPECT_GT(off.ratio(), 1.3);
  EXPECT_GT(off.near, 1.5 * on.near);
}

// SVGF: the Blender lamp's albedo (12) is no reflectance, so its pixels leave the a-trous guide
// with SVGF's default settings (excludeEmitters off: src/passes/emitters.h, reflectanceless()),
// as with excludeEmitters=true. That cuts the error next to the lamp by 31% (0.0436 to 0.0300)
// and lowers the ratio below 3.3 (2.91). The old cause present (the lamp in the filter:
// emitterThreshold so high that nothing is an emitter, which was the default's behaviour here
// before) fails the same bound (3.96). The rest is the a-trous levels' over-smoothing of the
// ceiling's own illumination and TAA (file comment), so the bound is looser than BMFR's.
TEST_F(BlenderLamp, SvgfLeavesTheLampOutOfTheCeilingsFilter) {
  const Halo now = measure("svgf", {});
  const Halo old = measure("svgf", {{"emitterThreshold", "1e9"}});
  EXPECT_LT(now.ratio(), 3.3);
  EXPECT_GT(old.ratio(), 3.3);
  EXPECT_LT(now.near, 0.8 * old.near);
  EXPECT_LT(now.far, 1.05 * old.far);  // elsewhere no worse
  const Halo dundr = measure("svgf", {{"variant", "dundr"}});
  EXPECT_LT(dundr.ratio(), 3.3);
  // With one a-trous level the lamp's neighbourhood is no worse than 2x the rest: what is left
  // at five levels is the filter's reach, not the lamp.
  const Halo oneLevel = measure("svgf", {{"atrousIterations", "1"}});
  EXPECT_LT(oneLevel.ratio(), 2.0);
}
#endif

}  // namespace
}  // namespace rtd
