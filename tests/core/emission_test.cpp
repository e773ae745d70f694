// Primary-hit emission (Buffer::Emission) is noise-free: every CPU method subtracts it before
// filtering and adds it back, so it is exactly additive and cannot bleed into neighbours (with
// the emitter exclusion off: on, the emitter pixels also leave the filter).
#include <gtest/gtest.h>

#include "support/test_frames.h"
#include "synthetic/synthetic.h"

namespace rtd {
namespace {

TEST(Emission, IsExactlyAdditiveForEveryCpuMethod) {
  synthetic::Scene scene;
  scene.width = 48;
  scene.height = 32;
  const float kEmission = 50.0f;  // a bright emitter: 100x the scene's radiance
  auto emitter = [](int x, int y) { return x >= 20 && x < 26 && y >= 10 && y < 16; };

  for (const auto& m : listMethods()) {
    if (!m.cpu) continue;
    auto plain = Device::create()->createDenoiser(m.name);
    auto lit = Device::create()->createDenoiser(m.name);
    // The emitter exclusion (svgf, bmfr) takes the emitter out of the filter on purpose
    // (tests/passes/emitters_test.cpp); additivity is that of the emission alone.
    for (const SettingInfo& info : lit->settings())
      if (info.name == "excludeEmitters") lit->set("excludeEmitters", "false");
    Image outPlain(scene.width, scene.height, 3), outLit(scene.width, scene.height, 3);
    for (int k = 0; k < 4; ++k) {
      Frame f = synthetic::makeFrame(scene, k);
      plain->denoise(f.inputs(), outPlain.view());
      Frame g = f;
      g[Buffer::Emission] = Image(scene.width, scene.height, 3, 0.0f);
      for (int y = 0; y < scene.height; ++y)
        for (int x = 0; x < scene.width; ++x)
          if (emitter(x, y))
            for (int c = 0; c < 3; ++c) {
              g[Buffer::Emission].at(x, y, c) = kEmission;
              g[Buffer::Color].at(x, y, c) += kEmission;
            }
      lit->denoise(g.inputs(), outLit.view());
    }
    for (int y = 0; y < scene.height; ++y)
      for (int x = 0; x < scene.width; ++x)
        for (int c = 0; c < 3; ++c) {
          const float expected = outPlain.at(x, y, c) + (emitter(x, y) ? kEmission : 0.0f);
          ASSERT_NEAR(outLit.at(x, y, c), expected, 1e-4f * (1.0f + expected)) << m.name << " at " << x << "," << y;
        }
  }
}

}  // namespace
}  // namespace rtd
