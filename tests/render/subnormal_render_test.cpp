// The renderer's hot loops compute no subnormal floats (src/core/flush.h, issue 20): every
// built-in scene's buffers and a reference, rendered on one thread with the MXCSR exception
// flags cleared, raise neither the denormal-operand nor the underflow flag, and no buffer
// holds a subnormal value.
#ifdef HAVE_RTDENOISE_RENDER
#include <gtest/gtest.h>

#include <cmath>

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

}  // namespace
}  // namespace rtd::render
#endif
