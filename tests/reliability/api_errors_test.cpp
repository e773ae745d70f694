// Issue 21: no exception other than rtd::Error (and std::bad_alloc) leaves the public API. A
// sweep of misuse on every method and both backends (tiny and degenerate sizes, calls out of
// order, settings and buffers changing between frames, wrong settings types), where each call
// must succeed or throw rtd::Error; the Vulkan BMFR once let std::out_of_range escape. And the
// guard the entry points use turns any other exception into an rtd::Error naming the call.
#include <gtest/gtest.h>

#include <functional>
#include <stdexcept>
#include <vector>

#include "core/api_guard.h"
#include "rtd/rtd.h"
#include "support/backends.h"
#include "synthetic/synthetic.h"

namespace rtd::test {
namespace {

// Runs fn; fails the test if it throws anything but rtd::Error.
void onlyRtdErrors(const std::string& what, const std::function<void()>& fn) {
  try {
    fn();
  } catch (const Error&) {
  } catch (const std::exception& e) {
    ADD_FAILURE() << what << ": " << typeid(e).name() << ": " << e.what();
  }
}

TEST(ApiErrors, GuardTurnsForeignExceptionsIntoRtdErrors) {
  try {
    guarded("denoise", [] { return std::vector<int>{}.at(size_t(-1)); });
    FAIL() << "no exception";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("denoise: internal error"), std::string::npos) << e.what();
  }
  EXPECT_THROW(guarded("x", [] { throw Error("bad input"); }), Error);
  EXPECT_THROW(guarded("x", [] { throw std::bad_alloc(); }), std::bad_alloc);
  EXPECT_EQ(guarded("x", [] { return 7; }), 7);
}

TEST(ApiErrors, MisuseOfEveryMethodOnBothBackendsRaisesOnlyRtdErrors) {
  for (Backend backend : testBackends()) {
    Device* device = testDevice(backend);
    if (!device) continue;
    for (const MethodInfo& m : listMethods()) {
      if (!(backend == Backend::Cpu ? m.cpu : m.vulkan)) continue;
      const std::string where = std::string(backendName(backend)) + " " + m.name;
      for (const auto& size : std::vector<std::pair<int, int>>{{1, 1}, {2, 3}, {1, 70}, {70, 1}, {33, 65}}) {
        // Named copies, not a structured binding: clang 14 (the asan build) cannot capture those.
        const int w = size.first, h = size.second;
        synthetic::Scene scene;
        scene.width = w;
        scene.height = h;
        const std::string at = where + " " + std::to_string(w) + "x" + std::to_string(h);
        onlyRtdErrors(at, [&] {
          auto d = device->createDenoiser(m.name);
          d->reset();  // before any frame
          (void)d->stats();
          Image out(w, h, 3);
          for (int i = 0; i < 3; ++i) {
            Frame f = synthetic::makeFrame(scene, i);
            FrameInputs in = f.inputs();
            if (i == 1) {  // optional buffers disappear for a frame, the camera with them
              in[Buffer::Motion] = {};
              in[Buffer::Roughness] = {};
              in[Buffer::ObjectId] = {};
              in.camera.valid = false;
            }
            onlyRtdErrors(at + " frame " + std::to_string(i), [&] { d->denoise(in, out.view()); });
          }
        });
      }
      // Settings changed between frames, to every choice of every enum and the ends of every range.
      onlyRtdErrors(where + " settings between frames", [&] {
        auto d = device->createDenoiser(m.name);
        synthetic::Scene scene;
        scene.width = 24;
        scene.height = 16;
        Image out(scene.width, scene.height, 3);
        int frame = 0;
        for (const SettingInfo& s : d->settings()) {
          std::vector<std::string> values = s.choices;
          if (s.type == "bool") values = {"false", "true"};
          for (const std::string& v : values) {
            onlyRtdErrors(where + " " + s.name + "=" + v, [&] { d->set(s.name, v); });
            onlyRtdErrors(where + " after " + s.name + "=" + v,
                          [&] { d->denoise(synthetic::makeFrame(scene, frame++ % 4).inputs(), out.view()); });
          }
        }
      });
      onlyRtdErrors(where + " wrong settings type", [&] {
        auto d = device->createDenoiser(m.name);
        if (m.name == "bmfr") EXPECT_THROW(d->setSettings(AccumulateSettings{}), Error) << where;
        else EXPECT_THROW(d->setSettings(BmfrSettings{}), Error) << where;
      });
    }
    onlyRtdErrors("unknown method", [&] { device->createDenoiser("nope"); });
  }
  onlyRtdErrors("negative threads", [] { Device::create({.backend = Backend::Cpu, .threads = -1}); });
  EXPECT_THROW(Device::create({.backend = Backend::Cpu, .threads = -1}), Error);
}

}  // namespace
}  // namespace rtd::test
