// The shared per-pixel passes take eight pixels at a time where they can (Bilinear8); these
// tests check those fast paths against the scalar definitions on random data, and the plane
// allocator they rely on.
#include <gtest/gtest.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <set>
#include <string>

#include "passes/demodulation.h"
#include "passes/reprojection.h"
#include "passes/temporal_accumulation.h"
#include "support/cpu_paths.h"

namespace rtd {
namespace {

struct Lcg {
  uint32_t state = 2024;
  float operator()() {
    state = state * 1664525u + 1013904223u;
    return float(state >> 8) / 16777216.0f;
  }
};

// A frame of flat features (every tap valid) whose motion is consecutive in some runs of
// eight pixels and random in others, so both the vector-load and the gather path run.
FrameData frameWithMotion(int w, int h, Lcg& rnd, bool withMotion) {
  FrameData f;
  f.width = w;
  f.height = h;
  f.buffers[int(Buffer::Depth)].assign(1, Plane(w, h, 3.0f));
  f.buffers[int(Buffer::Normal)] = {Plane(w, h, 0.0f), Plane(w, h, 0.0f), Plane(w, h, 1.0f)};
  if (withMotion) {
    f.buffers[int(Buffer::Motion)] = {Plane(w, h), Plane(w, h)};
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const bool uniform = (x / 8 + y) % 2 == 0;
        f.plane(Buffer::Motion, 0)(x, y) = uniform ? 1.3f : 4.0f * rnd() - 2.0f;
        f.plane(Buffer::Motion, 1)(x, y) = uniform ? -0.6f : 4.0f * rnd() - 2.0f;
      }
  }
  return f;
}

constexpr int kWidth = 75, kHeight = 23;

// A first frame (no history) and a second one with motion, and their reprojections.
struct TwoFrames {
  FrameData prev, cur;
  Reprojection none, rp;
  explicit TwoFrames(Lcg& rnd)
      : prev(frameWithMotion(kWidth, kHeight, rnd, false)), cur(frameWithMotion(kWidth, kHeight, rnd, true)) {
    reproject(prev, nullptr, ReprojectionSettings{}, none);
    reproject(cur, &prev, ReprojectionSettings{}, rp);
  }
};

// The history an accumulation read (copied before run(), which swaps its buffers).
struct History {
  Plane3 color;
  Plane length, m1, m2;
  explicit History(const TemporalAccumulator& acc)
      : color(acc.color()), length(acc.historyLength()), m1(acc.moment1()), m2(acc.moment2()) {}
};

// Pixel i of `acc` is the definition of a sampled pixel with bilinear history (Schied Sec. 4.1,
// cumulative moments): n = min(round(N) + 1, 255), the new sample weighed max(1/n, 0.2), its
// moments max(1/n, 0.1).
void expectBlended(const TemporalAccumulator& acc, const Reprojection& rp, const Plane3& current, const History& h,
                   size_t i) {
  const float n = std::min(std::round(rp.gather(h.length, i)) + 1.0f, 255.0f);
  EXPECT_EQ(acc.historyLength().data[i], n) << i;
  const float a = std::max(1.0f / n, 0.2f), am = std::max(1.0f / n, 0.1f);
  const float l = luminance(current[0].data[i], current[1].data[i], current[2].data[i]);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(acc.color()[c].data[i], a * current[c].data[i] + (1 - a) * rp.gather(h.color[c], i), 1e-6f) << i;
  EXPECT_NEAR(acc.moment1().data[i], am * l + (1 - am) * rp.gather(h.m1, i), 1e-6f) << i;
  EXPECT_NEAR(acc.moment2().data[i], am * l * l + (1 - am) * rp.gather(h.m2, i), 1e-6f) << i;
}

TEST(SharedPassPaths, AccumulationMatchesTheScalarDefinitionOnRandomMotion) {
  const int w = kWidth, h = kHeight;
  Lcg rnd;
  const TwoFrames frames(rnd);
  const Reprojection &none = frames.none, &rp = frames.rp;
  const auto counts = rp.counts();
  ASSERT_GT(counts[Reprojection::Bilinear], size_t(w * h / 2));

  auto image = [&] {
    Plane3 p;
    resize(p, w, h);
    for (auto& c : p)
      for (float& v : c.data) v = rnd();
    return p;
  };
  const Plane3 first = image(), second = image();
  TemporalAccumulator acc;
  acc.resize(w, h);
  for (int k = 0; k < 3; ++k) acc.run(none, first, 0.2f, 0.2f, 255);  // history length 3 everywhere
  const History before(acc);
  acc.run(rp, second, 0.2f, 0.1f, 255);
  for (size_t i = 0; i < size_t(w) * h; ++i)
    if (rp.kind[i] == Reprojection::Bilinear) expectBlended(acc, rp, second, before, i);

  // BMFR's phase III accumulation of three planes with the same taps.
  Plane3 out;
  resize(out, w, h);
  const Plane3 history = image();
  for (int y = 0; y < h; ++y) {
    const float* row[3] = {second[0].row(y), second[1].row(y), second[2].row(y)};
    accumulateRow(rp, acc.historyLength(), 0.1f, row, history, out, y);
  }
  for (size_t i = 0; i < size_t(w) * h; ++i) {
    if (rp.kind[i] == Reprojection::None) continue;
    const float a = std::max(1.0f / acc.historyLength().data[i], 0.1f);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(out[c].data[i], a * second[c].data[i] + (1 - a) * rp.gather(history[c], i), 1e-6f) << i;
  }
}

// A-SVGF's adaptive history (AccumulationOptions::temporalGradient) on random motion and random
// per-stratum gradients, on every CPU path: the eight-pixel path and the scalar one against the
// definition N' = min(N (1-G)^e + 1, cap), alpha = mix(max(1/N', floor), 1, G), for an integral
// exponent (vectorized) and a fractional one (scalar only).
TEST(SharedPassPaths, AdaptiveAccumulationMatchesTheDefinitionOnRandomMotion) {
  const int w = kWidth, h = kHeight;
  for (CpuPath path : test::supportedCpuPaths())
    for (float exponent : {10.0f, 2.5f}) {
      test::ScopedCpuPath force(path);
      SCOPED_TRACE(std::string(cpuPathName(path)) + " exponent " + std::to_string(exponent));
      Lcg rnd;
      const TwoFrames frames(rnd);
      const Reprojection &none = frames.none, &rp = frames.rp;
      auto image = [&] {
        Plane3 p;
        resize(p, w, h);
        for (auto& c : p)
          for (float& v : c.data) v = rnd();
        return p;
      };
      const Plane3 first = image(), second = image();
      Plane gradient((w + 2) / 3, (h + 2) / 3);
      for (float& g : gradient.data) g = 1.2f * rnd() - 0.1f;  // some outside [0, 1]: clamped
      AccumulationOptions opt;
      opt.temporalGradient = &gradient;
      opt.historyExponent = exponent;
      TemporalAccumulator acc;
      acc.resize(w, h);
      for (int k = 0; k < 3; ++k) acc.run(none, first, 0.1f, 0.01f, 256, opt);
      const Plane3 hColor = acc.color();
      const Plane hLength = acc.historyLength(), hM1 = acc.moment1(), hM2 = acc.moment2();
      acc.run(rp, second, 0.1f, 0.01f, 256, opt);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const size_t i = size_t(y) * w + x;
          if (rp.kind[i] == Reprojection::None) continue;
          const double g = std::clamp(gradient(x / 3, y / 3), 0.0f, 1.0f);
          const double n = std::min(rp.gather(hLength, i) * std::pow(1.0 - g, double(exponent)) + 1.0, 256.0);
          ASSERT_NEAR(acc.historyLength().data[i], n, 1e-5 * n) << i;
          const double a0 = std::max(1.0 / n, 0.1), a = a0 + (1 - a0) * g;
          const double am0 = std::max(1.0 / n, 0.01), am = am0 + (1 - am0) * g;
          const double l = luminance(second[0].data[i], second[1].data[i], second[2].data[i]);
          for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(acc.color()[c].data[i], a * second[c].data[i] + (1 - a) * rp.gather(hColor[c], i), 1e-5) << i;
          EXPECT_NEAR(acc.moment1().data[i], am * l + (1 - am) * rp.gather(hM1, i), 1e-5) << i;
          EXPECT_NEAR(acc.moment2().data[i], am * l * l + (1 - am) * rp.gather(hM2, i), 1e-5) << i;
        }
    }
}

// Three planes of uniform random values in [0, 1).
Plane3 randomColour(Lcg& rnd, int w, int h) {
  Plane3 p;
  resize(p, w, h);
  for (auto& c : p)
    for (float& v : c.data) v = rnd();
  return p;
}

// Progressive mode's sample mask (AccumulationOptions::sampleMask, Dundr Sec. 5) on every CPU
// path: a pixel with mask 0 keeps its history (length, colour and moments as reprojected), one
// with a sample blends as without a mask. Most groups of eight pixels are wholly sampled (the
// eight-pixel path takes them; a renderer's 1-spp frames have a mask of ones), the others mix
// both kinds.
TEST(SharedPassPaths, MaskedAccumulationMatchesTheDefinitionOnEveryPath) {
  const int w = kWidth, h = kHeight;
  for (CpuPath path : test::supportedCpuPaths()) {
    test::ScopedCpuPath force(path);
    SCOPED_TRACE(cpuPathName(path));
    Lcg rnd;
    const TwoFrames frames(rnd);
    const Reprojection &none = frames.none, &rp = frames.rp;
    const Plane3 first = randomColour(rnd, w, h), second = randomColour(rnd, w, h);
    Plane mask(w, h, 1.0f);
    size_t holes = 0;
    for (int y = 0; y < h; ++y)
      for (int x0 = 0; x0 < w; x0 += 8)
        if (rnd() < 0.3f)
          for (int x = x0; x < std::min(x0 + 8, w); ++x)
            if (rnd() < 0.5f) mask(x, y) = 0.0f, ++holes;
    ASSERT_GT(holes, size_t(w * h / 20));
    TemporalAccumulator acc;
    acc.resize(w, h);
    for (int k = 0; k < 3; ++k) acc.run(none, first, 0.2f, 0.1f, 255);  // history length 3 everywhere
    const History before(acc);
    AccumulationOptions opt;
    opt.sampleMask = &mask;
    acc.run(rp, second, 0.2f, 0.1f, 255, opt);
    size_t sampled = 0;
    for (size_t i = 0; i < size_t(w) * h; ++i) {
      if (rp.kind[i] != Reprojection::Bilinear) continue;
      if (mask.data[i] != 0.0f) {
        ++sampled;
        expectBlended(acc, rp, second, before, i);
        continue;
      }
      EXPECT_EQ(acc.historyLength().data[i], std::round(rp.gather(before.length, i))) << i;
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(acc.color()[c].data[i], rp.gather(before.color[c], i), 1e-6f) << i;
      EXPECT_NEAR(acc.moment1().data[i], rp.gather(before.m1, i), 1e-6f) << i;
      EXPECT_NEAR(acc.moment2().data[i], rp.gather(before.m2, i), 1e-6f) << i;
    }
    EXPECT_GT(sampled, size_t(w * h / 2));
  }
}

// Without moments (AccumulationOptions::moments = false, BMFR's phase I), the colour and the
// history length are exactly those with moments, whether run whole or in bands of rows, and
// the moment planes are left as they were.
TEST(SharedPassPaths, AccumulationWithoutMomentsKeepsColourAndLength) {
  const int w = kWidth, h = kHeight;
  Lcg rnd;
  const TwoFrames frames(rnd);
  const Plane3 first = randomColour(rnd, w, h), second = randomColour(rnd, w, h);
  TemporalAccumulator with, without;
  with.resize(w, h);
  without.resize(w, h);
  AccumulationOptions noMoments;
  noMoments.moments = false;
  for (int k = 0; k < 3; ++k) {
    with.run(frames.none, first, 0.2f, 0.2f, 255);
    without.run(frames.none, first, 0.2f, 0.2f, 255, noMoments);
  }
  const Plane staleM1 = without.moment1();
  with.run(frames.rp, second, 0.2f, 0.2f, 255);
  without.advance();
  for (int y = 0; y < h; y += 5) without.accumulateRows(frames.rp, second.data(), 0.2f, 0.2f, 255, noMoments, y, std::min(h, y + 5));
  for (size_t i = 0; i < size_t(w) * h; ++i) {
    ASSERT_EQ(without.historyLength().data[i], with.historyLength().data[i]) << i;
    for (int c = 0; c < 3; ++c) ASSERT_EQ(without.color()[c].data[i], with.color()[c].data[i]) << i;
  }
  // Two runs later the buffer holds what it held before the first: nothing wrote it.
  without.run(frames.rp, second, 0.2f, 0.2f, 255, noMoments);
  for (size_t i = 0; i < size_t(w) * h; ++i) ASSERT_EQ(without.moment1().data[i], staleM1.data[i]) << i;
}

// An accumulator resized without moments (BMFR's) keeps no moment planes, accumulates what one
// with them accumulates, and refuses a run that asks for moments.
TEST(SharedPassPaths, AccumulatorResizedWithoutMomentsKeepsNoMomentPlanes) {
  const int w = kWidth, h = kHeight;
  Lcg rnd;
  const TwoFrames frames(rnd);
  const Plane3 first = randomColour(rnd, w, h), second = randomColour(rnd, w, h);
  TemporalAccumulator with, without;
  with.resize(w, h);
  without.resize(w, h, /*moments=*/false);
  size_t kept = 0;
  without.forEachPlane([&](std::string_view name, const float*, size_t n) {
    if (name.substr(0, 6) == "moment") kept += n;
  });
  EXPECT_EQ(kept, 0u);
  AccumulationOptions noMoments;
  noMoments.moments = false;
  for (auto* acc : {&with, &without}) {
    for (int k = 0; k < 3; ++k) acc->run(frames.none, first, 0.2f, 0.2f, 255, noMoments);
    acc->run(frames.rp, second, 0.2f, 0.2f, 255, noMoments);
  }
  for (size_t i = 0; i < size_t(w) * h; ++i) {
    ASSERT_EQ(without.historyLength().data[i], with.historyLength().data[i]) << i;
    for (int c = 0; c < 3; ++c) ASSERT_EQ(without.color()[c].data[i], with.color()[c].data[i]) << i;
  }
  EXPECT_THROW(without.run(frames.rp, second, 0.2f, 0.2f, 255), std::logic_error);
}

// Demodulating on the fly (AccumulationOptions::albedo) gives exactly what demodulate()
// followed by the accumulation gives, albedo below the epsilon included, on every CPU path;
// AccumulationOptions::current then holds exactly demodulate()'s planes (SVGF's variance
// reads them), with or without a sample mask.
TEST(SharedPassPaths, OnTheFlyDemodulationEqualsTheDemodulatePass) {
  const int w = kWidth, h = kHeight;
  for (const CpuPath path : test::supportedCpuPaths()) {
    const test::ScopedCpuPath scoped(path);
    for (const bool masked : {false, true}) {
      SCOPED_TRACE(std::string(cpuPathName(path)) + (masked ? ", sample mask" : ""));
      Lcg rnd;
      const TwoFrames frames(rnd);
      const Reprojection &none = frames.none, &rp = frames.rp;
      auto planes = [&](float zeroShare) {
        std::vector<Plane> p(3, Plane(w, h));
        for (auto& c : p)
          for (float& v : c.data) v = rnd() < zeroShare ? 0.0f : rnd();
        return p;
      };
      const std::vector<Plane> albedo = planes(0.1f);
      Plane mask(w, h);
      for (float& v : mask.data) v = rnd() < 0.25f ? 1.0f : 0.0f;
      TemporalAccumulator fused, separate;
      fused.resize(w, h);
      separate.resize(w, h);
      Plane3 current;
      resize(current, w, h);
      AccumulationOptions fusedOptions, separateOptions;
      fusedOptions.albedo = &albedo;
      fusedOptions.current = &current;
      if (masked) fusedOptions.sampleMask = separateOptions.sampleMask = &mask;
      for (const Reprojection* r : {&none, &rp}) {
        const std::vector<Plane> radiance = planes(0.0f);
        Plane3 demodulated;
        demodulate(radiance, &albedo, demodulated);
        fused.run(*r, radiance, 0.2f, 0.2f, 255, fusedOptions);
        separate.run(*r, demodulated, 0.2f, 0.2f, 255, separateOptions);
        for (int c = 0; c < 3; ++c) ASSERT_EQ(current[c].data, demodulated[c].data);
      }
      for (int c = 0; c < 3; ++c) EXPECT_EQ(fused.color()[c].data, separate.color()[c].data);
      EXPECT_EQ(fused.moment1().data, separate.moment1().data);
      EXPECT_EQ(fused.moment2().data, separate.moment2().data);
      EXPECT_EQ(fused.historyLength().data, separate.historyLength().data);
    }
  }
}

// Bilinear8 reads a group of eight pixels' taps with one load where the eight footprints are
// consecutive and with a gather otherwise. Three motion fields, making consecutive groups,
// groups within 16 elements of one row (which a windowed read, tried in session 7, would
// take) and scattered groups the common case (checked on the bases), on every CPU path: the reprojection's
// tap tests (a previous normal plane that rejects about a third of the taps, so a tap read
// from the wrong pixel changes the weights) equal the sse2 path's, and the accumulation and
// BMFR's phase III equal the scalar definition (random history) to float rounding.
TEST(SharedPassPaths, WindowedAndGatheredTapsEqualTheScalarDefinition) {
  const int w = 93, h = 29;
  enum Field { Uniform, Jittered, Scattered };
  for (const Field field : {Uniform, Jittered, Scattered}) {
    Lcg rnd;
    FrameData prev = frameWithMotion(w, h, rnd, false), cur = frameWithMotion(w, h, rnd, true);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const float mx = field == Uniform ? 2.3f : field == Jittered ? 2.3f + 1.6f * rnd() - 0.8f : 16.0f * rnd() - 8.0f;
        const float my = field == Uniform ? -0.6f : field == Jittered ? -0.6f + 0.8f * rnd() - 0.4f : 16.0f * rnd() - 8.0f;
        cur.plane(Buffer::Motion, 0)(x, y) = mx;
        cur.plane(Buffer::Motion, 1)(x, y) = my;
        if (rnd() < 0.3f) prev.plane(Buffer::Normal, 2)(x, y) = -1.0f;  // a tap here fails the normal test
      }
    ReprojectionSettings s;
    Reprojection ref, none;
    {
      const test::ScopedCpuPath scalar(CpuPath::Sse2);
      reproject(cur, &prev, s, ref);
    }
    reproject(prev, nullptr, s, none);
    // How the groups of eight the accumulation reads (x = 0, 8, ...) classify.
    size_t groups[3] = {};
    for (int y = 0; y < h; ++y)
      for (int x = 0; x + 8 <= w; x += 8) {
        const size_t i = size_t(y) * w + x;
        bool all = true, consecutive = true;
        int lo = INT32_MAX, hi = INT32_MIN;
        for (int k = 0; k < 8; ++k) {
          all = all && ref.kind[i + k] == Reprojection::Bilinear;
          consecutive = consecutive && ref.base[i + k] == ref.base[i] + k;
          lo = std::min(lo, ref.base[i + k]);
          hi = std::max(hi, ref.base[i + k]);
        }
        if (all) ++groups[consecutive ? 0 : hi - lo < 16 ? 1 : 2];
      }
    SCOPED_TRACE("motion field " + std::to_string(int(field)));
    const size_t total = groups[0] + groups[1] + groups[2];
    ASSERT_GT(groups[int(field)], total / 2) << groups[0] << " " << groups[1] << " " << groups[2];
    const auto counts = ref.counts();
    ASSERT_GT(counts[Reprojection::Bilinear], size_t(w * h) / 2);
    // Some taps are rejected (the plain bilinear weights of these fractional motions are all
    // positive, so a zero weight is a failed test or the border's slide).
    size_t rejected = 0;
    for (size_t i = 0; i < size_t(w) * h; ++i)
      if (ref.kind[i] == Reprojection::Bilinear &&
          std::find(ref.weights[i].begin(), ref.weights[i].end(), 0.0f) != ref.weights[i].end())
        ++rejected;
    ASSERT_GT(rejected, counts[Reprojection::Bilinear] / 5);

    for (const CpuPath path : test::supportedCpuPaths()) {
      const test::ScopedCpuPath scoped(path);
      SCOPED_TRACE(cpuPathName(path));
      Reprojection rp;
      reproject(cur, &prev, s, rp);
      for (size_t i = 0; i < size_t(w) * h; ++i) {
        ASSERT_EQ(rp.kind[i], ref.kind[i]) << i;
        if (rp.kind[i] == Reprojection::None) continue;
        ASSERT_EQ(rp.base[i], ref.base[i]) << i;
        for (int t = 0; t < 4; ++t) ASSERT_NEAR(rp.weights[i][t], ref.weights[i][t], 1e-6f) << i;
      }
      auto image = [&] {
        Plane3 p;
        resize(p, w, h);
        for (auto& c : p)
          for (float& v : c.data) v = rnd();
        return p;
      };
      const Plane3 first = image(), second = image(), history = image();
      TemporalAccumulator acc;
      acc.resize(w, h);
      for (int k = 0; k < 3; ++k) acc.run(none, first, 0.2f, 0.2f, 255);
      const Plane3 hColor = acc.color();
      const Plane hLength = acc.historyLength(), hM1 = acc.moment1(), hM2 = acc.moment2();
      acc.run(ref, second, 0.2f, 0.1f, 255);
      Plane3 out;
      resize(out, w, h);
      for (int y = 0; y < h; ++y) {
        const float* row[3] = {second[0].row(y), second[1].row(y), second[2].row(y)};
        accumulateRow(ref, acc.historyLength(), 0.1f, row, history, out, y);
      }
      for (size_t i = 0; i < size_t(w) * h; ++i) {
        if (ref.kind[i] == Reprojection::None) continue;
        const float n = std::min(std::round(ref.gather(hLength, i)) + 1.0f, 255.0f);
        ASSERT_EQ(acc.historyLength().data[i], n) << i;
        const float a = std::max(1.0f / n, 0.2f), am = std::max(1.0f / n, 0.1f), a3 = std::max(1.0f / n, 0.1f);
        const float l = luminance(second[0].data[i], second[1].data[i], second[2].data[i]);
        for (int c = 0; c < 3; ++c) {
          ASSERT_NEAR(acc.color()[c].data[i], a * second[c].data[i] + (1 - a) * ref.gather(hColor[c], i), 1e-6f) << i;
          ASSERT_NEAR(out[c].data[i], a3 * second[c].data[i] + (1 - a3) * ref.gather(history[c], i), 1e-6f) << i;
        }
        ASSERT_NEAR(acc.moment1().data[i], am * l + (1 - am) * ref.gather(hM1, i), 1e-6f) << i;
        ASSERT_NEAR(acc.moment2().data[i], am * l * l + (1 - am) * ref.gather(hM2, i), 1e-6f) << i;
      }
    }
  }
}

// Planes of one size must not share their offset within a page (see StaggeredAllocator).
TEST(SharedPassPaths, PlanesStartOnDistinctCacheLinesOfAPage) {
  std::vector<Plane> planes;
  for (int k = 0; k < 16; ++k) planes.emplace_back(1280, 720);
  std::set<uintptr_t> lines;
  for (const Plane& p : planes) {
    const auto address = reinterpret_cast<uintptr_t>(p.ptr());
    EXPECT_EQ(address % 64, 0u);
    lines.insert(address % 4096 / 64);
  }
  EXPECT_EQ(lines.size(), planes.size());
  // Copies and moves keep working with the allocator.
  Plane copy = planes[3];
  copy.data[5] = 7.0f;
  EXPECT_EQ(planes[3].data[5], 0.0f);
  EXPECT_EQ(copy.data.size(), planes[3].data.size());
}

}  // namespace
}  // namespace rtd
