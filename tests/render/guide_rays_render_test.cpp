// The renderer's guide-ray samples (RenderSettings::guideRays, Voorhuis Sec. 5): the guide frame
// is the 1-spp centre render, the other samples are jittered with their own primary hits, and
// guide-ray supersampling of an emitter's silhouette approaches the pixel-area reference.
#ifdef HAVE_RTDENOISE_RENDER
#include <gtest/gtest.h>

#include <cmath>

#include "render/render_test_util.h"
#include "rtd/error.h"
#include "rtd/guide_rays.h"

namespace rtd::render::test {
namespace {

// A black-bodied emissive quad (radiance exactly 1, nothing else lit: black sky) at depth 3,
// rotated so its edges are diagonal in the image; sky elsewhere.
constexpr const char* kEmitter = R"({
  "objects": [{"shape": "quad", "translation": [0.3, 0, -3], "rotation": [90, 0, 27], "scale": 1.6,
               "material": {"baseColor": 0, "specular": 0, "emissive": 1.0}}],
  "sky": {"color": 0},
  "camera": {"position": [0, 0, 0], "target": [0, 0, -1], "fov": 50}
})";

TEST(GuideRayRender, GuideFrameIsTheCentreSampleAndSamplesCarryTheirOwnHits) {
  const int w = 32, h = 24;
  RenderSettings one = tiny(w, h, 1), guide = tiny(w, h, 4);
  guide.guideRays = true;
  Renderer r1(sceneFromJson(kEmitter), one), r4(sceneFromJson(kEmitter), guide);
  const Frame f1 = r1.render(0);
  GuideRaySamples s;
  const Frame g = r4.render(0, Eye::Center, s);
  ASSERT_EQ(s.samples.size(), 3u);
  // Sample 0 of a guide-ray render is the 1-spp render exactly (same seed, pixel centre).
  EXPECT_EQ(g[Buffer::Color].pixels, f1[Buffer::Color].pixels);
  EXPECT_EQ(g[Buffer::Depth].pixels, f1[Buffer::Depth].pixels);
  int onQuad = 0, onSky = 0;
  for (size_t k = 0; k < s.samples.size(); ++k)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const float ox = s.offsets[k].at(x, y, 0), oy = s.offsets[k].at(x, y, 1);
        ASSERT_TRUE(ox >= -0.5f && ox <= 0.5f && oy >= -0.5f && oy <= 0.5f);
        const float c = s.samples[k][Buffer::Color].at(x, y, 1), z = s.samples[k][Buffer::Depth].at(x, y);
        const float nz = s.samples[k][Buffer::Normal].at(x, y, 2);
        if (c > 0.5f) {  // on the quad: radiance 1, depth 3 - (tilt) and its normal
          ++onQuad;
          EXPECT_NEAR(c, 1.0f, 1e-5f);
          EXPECT_NEAR(z, 3.0f, 1e-3f);
          EXPECT_NEAR(nz, 1.0f, 1e-4f);
        } else {  // sky: black, the guides' sky depth, no normal
          ++onSky;
          EXPECT_EQ(c, 0.0f);
          EXPECT_GE(z, 1e3f);
          EXPECT_EQ(nz, 0.0f);
        }
      }
  EXPECT_GT(onQuad, 100);
  EXPECT_GT(onSky, 100);
}

TEST(GuideRayRender, SupersampledSilhouetteApproachesThePixelAreaReference) {
  // Checklist 22 (b) on rendered samples: 16 spp with guide rays, each sample joining a guide
  // on its own surface (quad or sky) and taking its colour back; with no filter in between the
  // result is the per-pixel share of samples on the quad, against a 1024-spp jittered reference.
  const int w = 40, h = 30;
  RenderSettings gs = tiny(w, h, 16);
  gs.guideRays = true;
  Renderer r(sceneFromJson(kEmitter), gs);
  GuideRaySamples s;
  const Frame g = r.render(0, Eye::Center, s);
  GuideRays gr;
  const Frame mixed = gr.premix(g, s);
  const Image aa = gr.resolve(mixed[Buffer::Color]);
  RenderSettings rs = tiny(w, h, 1);
  rs.pixelJitter = true;
  Renderer rr(sceneFromJson(kEmitter), rs);
  const Image ref = rr.renderReference(0, 1024);
  double errAa = 0, errGuides = 0;
  int edge = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float cover = ref.at(x, y, 1);
      if (cover < 0.02f || cover > 0.98f) continue;
      ++edge;
      errAa += std::abs(aa.at(x, y, 1) - cover);
      errGuides += std::abs(g[Buffer::Color].at(x, y, 1) - cover);
    }
  ASSERT_GT(edge, 30);
  errAa /= edge;
  errGuides /= edge;
  EXPECT_LT(errAa, 0.1) << edge << " edge pixels";
  EXPECT_LT(errAa, 0.35 * errGuides);
}

TEST(GuideRayRender, SettingsThatCannotGiveGuideRaysAreRefused) {
  RenderSettings s = tiny(8, 8, 4);
  s.guideRays = true;
  s.pixelJitter = true;
  EXPECT_THROW({ Renderer bad(sceneFromJson(kEmitter), s); }, rtd::Error);
  RenderSettings plain = tiny(8, 8, 4);
  Renderer r(sceneFromJson(kEmitter), plain);
  GuideRaySamples samples;
  EXPECT_THROW(r.render(0, Eye::Center, samples), rtd::Error);
}

}  // namespace
}  // namespace rtd::render::test
#endif
