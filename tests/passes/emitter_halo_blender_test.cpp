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

#include "rtd/rtd.h"
#include "support/ceiling_halo.h"
#ifdef HAVE_RTDENOISE_EVAL
#include "rtd/eval/evaluate.h"
#endif

namespace rtd {
namespace {

#ifdef HAVE_RTDENOISE_EVAL
const std::filesystem::path kLamp = std::filesystem::path(RTD_SOURCE_DIR) / "tests/fixtures/blender_lamp";

using test::CeilingHalo;

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
  static CeilingHalo measure(const std::string& method, const std::vector<std::pair<std::string, std::string>>& settings) {
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
    // The ceiling: downward normal at the ceiling's height (2.8 m, Blender's z up; the lamp is
    // at 2.798 m).
    const CeilingHalo r = test::ceilingHalo(last, out, reference, [&](int x, int y) {
      return last[Buffer::Normal].at(x, y, 2) < -0.9f && last[Buffer::Position].at(x, y, 2) > 2.79f;
    });
    EXPECT_GE(r.lampPixels, 40) << "the lamp is visible";
    EXPECT_GT(r.nNear, 100);
    EXPECT_GT(r.nFar, 300);
    std::string name = method;
    for (const auto& [k, v] : settings) name += " " + k + "=" + v;
    r.print(name);
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
  const CeilingHalo on = measure("bmfr", {});
  EXPECT_LT(on.ratio(), 1.3);
  const CeilingHalo off = measure("bmfr", {{"excludeEmitters", "false"}});
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
  const CeilingHalo now = measure("svgf", {});
  const CeilingHalo old = measure("svgf", {{"emitterThreshold", "1e9"}});
  EXPECT_LT(now.ratio(), 3.3);
  EXPECT_GT(old.ratio(), 3.3);
  EXPECT_LT(now.near, 0.8 * old.near);
  EXPECT_LT(now.far, 1.05 * old.far);  // elsewhere no worse
  const CeilingHalo dundr = measure("svgf", {{"variant", "dundr"}});
  EXPECT_LT(dundr.ratio(), 3.3);
  // With one a-trous level the lamp's neighbourhood is no worse than 2x the rest: what is left
  // at five levels is the filter's reach, not the lamp.
  const CeilingHalo oneLevel = measure("svgf", {{"atrousIterations", "1"}});
  EXPECT_LT(oneLevel.ratio(), 2.0);
}

// TAA's own-surface box (taaOwnSurface): next to the lamp the plain 3x3 box reads the lamp's
// pixels, whose filtered radiance is 0, so it reaches down to 0 and TAA keeps a downward bias;
// with the lamp's pixels a surface of their own (the emitter key of passes/taa_keys.h; the
// fixture's objects all have pass index 0, so that is its only key) they leave the ceiling's
// box. Measured: svgf 0.0300 (ratio 2.91) plain, 0.0283 (2.74) own-surface, 0.0263 (2.40)
// without TAA: the option removes 45% of what TAA adds next to the lamp, the rest is the
// ceiling's own pixels' history (the a-trous output's bias is also in the box). BMFR, which
// has no halo, is unchanged (0.0143, ratio 1.03 both).
TEST_F(BlenderLamp, OwnSurfaceTaaBoxKeepsTheLampOutOfTheCeilingsBox) {
  const CeilingHalo plain = measure("svgf", {{"taaOwnSurface", "false"}});
  const CeilingHalo own = measure("svgf", {{"taaOwnSurface", "true"}});  // the default
  EXPECT_LT(own.near, 0.0290);
  EXPECT_LT(own.near, plain.near - 0.001);
  EXPECT_LT(own.ratio(), 2.8);
  EXPECT_LE(own.far, 1.01 * plain.far);  // elsewhere no worse
  const CeilingHalo bmfr = measure("bmfr", {{"taaOwnSurface", "false"}});
  const CeilingHalo bmfrOwn = measure("bmfr", {{"taaOwnSurface", "true"}});
  EXPECT_LT(bmfrOwn.ratio(), 1.3);
  EXPECT_NEAR(bmfrOwn.near, bmfr.near, 0.02 * bmfr.near);
}
#endif

}  // namespace
}  // namespace rtd
