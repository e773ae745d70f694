// The renderer's hot loops compute no subnormal floats (src/core/flush.h, issue 20): every
// built-in scene's buffers and a reference, rendered on one thread with the MXCSR exception
// flags cleared, raise neither the denormal-operand nor the underflow flag, and no buffer
// holds a subnormal value.
#ifdef HAVE_RTDENOISE_RENDER
#include <gtest/gtest.h>

#include <tbb/parallel_for.h>

#include <cmath>
#include <mutex>
#include <set>
#include <thread>

#include "render/render_test_util.h"

#if defined(__x86_64__) || defined(__i386__)
#include <xmmintrin.h>
#endif

namespace rtd::render {
namespace {

unsigned subnormalFlags() {
#if defined(__x86_64__) || defined(__i386__)
  return _mm_getcsr() & 0x12u;  // underflow | denormal operand
#else
  return 0;
#endif
}
unsigned flushModes() {
#if defined(__x86_64__) || defined(__i386__)
  return _mm_getcsr() & 0x8040u;  // flush-to-zero | denormals-are-zero
#else
  return 0;
#endif
}
void clearFlags() {
#if defined(__x86_64__) || defined(__i386__)
  _mm_setcsr(_mm_getcsr() & ~0x3fu);
#endif
}

size_t subnormals(const Image& im) {
  size_t n = 0;
  for (float v : im.pixels) n += std::fpclassify(v) == FP_SUBNORMAL;
  return n;
}

TEST(RendererSubnormal, BuiltinScenesComputeNoSubnormals) {
  for (const std::string& name : Scene::builtinScenes()) {
    test::withThreads(1, [&] {
      auto scene = Scene::load(name);
      Renderer r(scene, test::tiny(40, 24));
      r.render(0);  // geometry and caches built outside the probe
      clearFlags();
      const Frame f = r.render(1);
      const unsigned frameFlags = subnormalFlags();
      clearFlags();
      const Image ref = r.renderReference(1, 4);
      const unsigned refFlags = subnormalFlags();
      EXPECT_EQ(frameFlags, 0u) << name << ": a subnormal in render()";
      EXPECT_EQ(refFlags, 0u) << name << ": a subnormal in renderReference()";
      for (int b = 0; b < kBufferCount; ++b)
        if (f.has(Buffer(b))) {
          EXPECT_EQ(subnormals(f.buffers[size_t(b)]), 0u) << name << " " << bufferName(Buffer(b));
        }
      EXPECT_EQ(subnormals(ref), 0u) << name;
    });
  }
}

// Embree's scene commit turns on flush-to-zero and denormals-are-zero on its calling thread
// while it builds (and restores them after). A oneTBB arena takes the floating-point mode of
// the thread that initializes it: where the build was the first oneTBB work of the calling
// thread, the thread's implicit arena was initialized inside that window and from then on ran
// every parallel loop of the application in that arena with FTZ/DAZ on its worker threads
// (the denoisers run on their device's own arena). A new thread has a fresh implicit arena,
// so the render below is its first oneTBB work, as in a program that renders before anything
// else.
TEST(RendererSubnormal, RenderingLeavesTheCallersFloatingPointModeAlone) {
  ASSERT_EQ(flushModes(), 0u) << "the suite must run in the default floating-point mode";
  std::set<unsigned> seen;
  unsigned caller = ~0u;
  std::thread([&] {
    Renderer r(Scene::load(Scene::builtinScenes().front()), test::tiny(32, 24));
    r.render(0);
    caller = flushModes();
    std::mutex m;
    tbb::parallel_for(0, 256, [&](int) {
      std::lock_guard lock(m);
      seen.insert(flushModes());
    });
  }).join();
  EXPECT_EQ(caller, 0u);
  EXPECT_EQ(seen, std::set<unsigned>{0u}) << "a parallel loop after the render ran with FTZ/DAZ";
}

}  // namespace
}  // namespace rtd::render
#endif
