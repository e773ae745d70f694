// A denoiser's history is all the state it carries from frame to frame: after reset() it runs
// as a fresh denoiser of the same settings, frame for frame, for every method on both
// backends. And a change of SVGF's preset followed by reset() leaves nothing of the old
// preset's state behind (the Voorhuis parts' classes and specular record once survived a switch
// to a preset without them: docs/performance.md, "Session 15").
#if defined(HAVE_RTDENOISE_RENDER)
#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

#include "rtd/render/render.h"
#include "rtd/rtd.h"
#include "support/backends.h"

namespace rtd::test {
namespace {

// Five frames of the built-in glossy scene (mirrors, glossy metals: every buffer any method
// reads, the reflection ones included), camera moving, at a size that is not a multiple of 16.
const std::vector<Frame>& frames() {
  static const std::vector<Frame> f = [] {
    render::RenderSettings rs;
    rs.width = 52;
    rs.height = 36;
    render::Renderer r(render::Scene::load("glossy"), rs);
    std::vector<Frame> out;
    for (int i = 0; i < 5; ++i) out.push_back(r.render(30 + i));
    return out;
  }();
  return f;
}

// `used` runs frames 0-2, then `beforeReset` (a change of settings), then reset(); it and a
// fresh denoiser `fresh` of its settings then run frames 3-4 and must agree. The two run the same code on the same input, so any
// difference is state that survived the reset; the tolerance only absorbs a reduction split
// across threads differently (none is expected).
void expectResetIsFresh(Denoiser& used, Denoiser& fresh, const std::string& what,
                        const std::function<void()>& beforeReset = {}) {
  const std::vector<Frame>& f = frames();
  Image a(f[0].width, f[0].height, 3), b(a.width, a.height, 3);
  for (int i = 0; i < 3; ++i) used.denoise(f[size_t(i)].inputs(), a.view());
  if (beforeReset) beforeReset();
  used.reset();
  for (int i = 3; i < 5; ++i) {
    used.denoise(f[size_t(i)].inputs(), a.view());
    fresh.denoise(f[size_t(i)].inputs(), b.view());
    const ErrorStats e = compare(a, b);
    for (int c = 0; c < 3; ++c) ASSERT_LE(e.maxAbs[c], 1e-6 * e.maxRef) << what << ", frame " << i << ": " << describe(e);
  }
}

TEST(Reset, EveryMethodAfterAResetRunsAsAFreshOneOnBothBackends) {
  for (Backend backend : testBackends()) {
    Device* device = testDevice(backend);
    if (!device) continue;
    for (const std::string& method : methodsOn(backend)) {
      auto used = device->createDenoiser(method);
      auto fresh = device->createDenoiser(method);
      expectResetIsFresh(*used, *fresh, method + (backend == Backend::Cpu ? " (CPU)" : " (Vulkan)"));
    }
  }
}

TEST(Reset, SvgfPresetSwitchedThenResetRunsAsAFreshOneOnBothBackends) {
  const std::vector<std::string> presets = {"schied", "dundr", "gersthofer", "voorhuis", "voorhuisBase",
                                            "voorhuisNoSpecReproj", "voorhuisRobustness"};
  for (Backend backend : testBackends()) {
    Device* device = testDevice(backend);
    if (!device) continue;
    // Every ordered pair on the CPU; on lavapipe each preset to the next and back (fewer frames).
    for (size_t i = 0; i < presets.size(); ++i)
      for (size_t j = 0; j < presets.size(); ++j) {
        if (i == j) continue;
        const bool neighbours = j == (i + 1) % presets.size() || i == (j + 1) % presets.size();
        if (backend == Backend::Vulkan && !neighbours) continue;
        auto used = device->createDenoiser("svgf");
        auto fresh = device->createDenoiser("svgf");
        used->set("variant", presets[i]);
        fresh->set("variant", presets[j]);
        expectResetIsFresh(*used, *fresh, presets[i] + " -> " + presets[j] + (backend == Backend::Cpu ? " (CPU)" : " (Vulkan)"),
                           [&] { used->set("variant", presets[j]); });
      }
  }
}

}  // namespace
}  // namespace rtd::test
#endif
