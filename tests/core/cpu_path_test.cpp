// Runtime dispatch (src/core/cpu_path.h): every CPU path this machine runs, forced in turn,
// gives the scalar reference's result: import and export bit for bit (Bounds::sanitize and the
// scalar interleave), reprojection's tap decisions exactly, and whole frames of every method
// within the stated tolerances of the sse2 path (whose reprojection, accumulation, TAA and
// import are the scalar reference code; the a-trous filter is checked against a double-precision
// reference on every path in svgf_test.cpp). RTD_CPU_PATH's errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <random>

#include "core/flush.h"
#include "core/frame_data.h"
#include "core/frame_data_kernels.h"
#include "core/sanitize.h"
#include "passes/reprojection.h"
#include "rtd/rtd.h"
#include "support/cpu_paths.h"
#include "synthetic/synthetic.h"

namespace rtd {
namespace {

using test::ScopedCpuPath;
using test::supportedCpuPaths;

TEST(CpuPath, DetectionAndNames) {
  EXPECT_TRUE(cpuPathSupported(CpuPath::Sse2));
  EXPECT_TRUE(cpuPathSupported(bestCpuPath()));
  for (int i = 0; i < kCpuPathCount; ++i)
    if (cpuPathSupported(CpuPath(i))) {
      EXPECT_LE(i, int(bestCpuPath()));
    }
  EXPECT_STREQ(cpuPathName(CpuPath::Avx512), "avx512");
  for (CpuPath p : supportedCpuPaths()) {
    ScopedCpuPath force(p);
    EXPECT_EQ(cpuPath(), p);
    EXPECT_NE(Device::create()->name().find(cpuPathName(p)), std::string::npos);
  }
  // A path the CPU lacks cannot be forced.
  for (int i = 0; i < kCpuPathCount; ++i)
    if (!cpuPathSupported(CpuPath(i))) {
      EXPECT_THROW(setCpuPath(CpuPath(i)), Error);
    }
}

TEST(CpuPath, EnvironmentVariableIsChecked) {
  const char* old = std::getenv("RTD_CPU_PATH");
  const std::string saved = old ? old : "";
  setenv("RTD_CPU_PATH", "avx9", 1);
  try {
    checkCpuPathSetting();
    ADD_FAILURE() << "an unknown path was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("avx9"), std::string::npos) << e.what();
  }
  EXPECT_THROW(Device::create(), Error);
  for (const char* ok : {"auto", "sse2"}) {
    setenv("RTD_CPU_PATH", ok, 1);
    EXPECT_NO_THROW(checkCpuPathSetting()) << ok;
  }
  for (int i = 0; i < kCpuPathCount; ++i) {
    setenv("RTD_CPU_PATH", cpuPathName(CpuPath(i)), 1);
    if (cpuPathSupported(CpuPath(i))) {
      EXPECT_NO_THROW(checkCpuPathSetting());
    }
    else EXPECT_THROW(checkCpuPathSetting(), Error);
  }
  if (old) setenv("RTD_CPU_PATH", saved.c_str(), 1);
  else unsetenv("RTD_CPU_PATH");
}

// Values import must replace (NaN, infinities, negatives for radiance, above 3e38), flush
// (subnormal and tiny) or keep, in every lane position.
float awkwardValue(std::mt19937& rng) {
  const float values[] = {0.0f, -0.0f, 1.0f, -2.5f, 1e-40f, -1e-39f, 1e-20f, 0x1p-60f, 0x1p-61f, 3e38f, 3.2e38f,
                          std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                          std::numeric_limits<float>::quiet_NaN(), 0.5f, 1234.5f};
  return values[rng() % (sizeof values / sizeof values[0])];
}

TEST(CpuPath, ImportAndExportMatchTheScalarReferenceExactly) {
  const int w = 45, h = 7;  // not a multiple of 8 or 16
  std::mt19937 rng(3);
  Frame f;
  f.width = w;
  f.height = h;
  // (Not the unit-vector buffers, which import renormalizes afterwards.)
  const Buffer buffers[] = {Buffer::Color, Buffer::Depth, Buffer::Motion, Buffer::Albedo, Buffer::Roughness};
  for (Buffer b : buffers) {
    // Albedo with 4 floats per pixel (an RGBA source): the stride-4 de-interleave.
    const int channels = b == Buffer::Albedo ? 4 : bufferChannelCount(b);
    f[b] = Image(w, h, channels);
    for (float& v : f[b].pixels) v = awkwardValue(rng);
  }
  FrameInputs in = f.inputs();
  in[Buffer::Albedo].format = Format::Float4;
  for (CpuPath p : supportedCpuPaths()) {
    ScopedCpuPath force(p);
    FrameData d;
    SanitizeStats counts{};
    importFrame(in, {Buffer::Color}, d, nullptr, &counts);
    for (Buffer b : buffers) {
      const ValueRange range = importRange(b);
      const Bounds bounds{range.lo, range.hi};
      SanitizeCounts expect;
      const int nc = bufferChannelCount(b), stride = f[b].channels;
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          for (int c = 0; c < nc; ++c) {
            const float want = bounds.sanitize(f[b].pixels[(size_t(y) * w + x) * stride + c], expect);
            const float got = d.plane(b, c)(x, y);
            ASSERT_EQ(std::bit_cast<uint32_t>(got), std::bit_cast<uint32_t>(want))
                << cpuPathName(p) << " " << bufferName(b) << " " << x << "," << y << "," << c;
          }
      EXPECT_EQ(counts[size_t(b)].nonFinite, expect.nonFinite) << cpuPathName(p) << " " << bufferName(b);
      EXPECT_EQ(counts[size_t(b)].outOfRange, expect.outOfRange) << cpuPathName(p) << " " << bufferName(b);
    }

    // Export: planes (plus emission) into Float3 and Float4 views.
    Plane3 rgb;
    resize(rgb, w, h);
    std::vector<Plane> emission(3, Plane(w, h));
    for (int c = 0; c < 3; ++c)
      for (size_t i = 0; i < rgb[c].size(); ++i) {
        rgb[c].data[i] = float(rng() % 1000) * 0.01f;
        emission[size_t(c)].data[i] = float(rng() % 7);
      }
    for (int channels : {3, 4})
      for (bool withEmission : {false, true}) {
        Image out(w, h, channels, -1.0f);
        exportRgb(rgb, withEmission ? &emission : nullptr, out.view());
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x)
            for (int c = 0; c < channels; ++c) {
              const float want = c == 3 ? 1.0f : rgb[c](x, y) + (withEmission ? emission[size_t(c)](x, y) : 0.0f);
              ASSERT_EQ(out.at(x, y, c), want) << cpuPathName(p) << " " << x << "," << y << "," << c;
            }
      }
  }
}

// Import's fused row fixes: normals renormalized and emission subtracted in the same pass as
// the sanitizer, on every path, against the scalar rules applied one after the other
// (Bounds::sanitize, then renormalize, then max(0, flushTiny(colour - emission))).
TEST(CpuPath, ImportRenormalizesAndSeparatesEmissionAsTheScalarRulesDo) {
  const int w = 45, h = 7;
  std::mt19937 rng(5);
  Frame f;
  f.width = w;
  f.height = h;
  for (Buffer b : {Buffer::Color, Buffer::Normal, Buffer::Emission}) f[b] = Image(w, h, 3);
  const float lengths[] = {1.0f, 1.0f, 1.5f, 0.2f, 1e-20f, 1e-39f, 0.0f, 1.0004f, 1.0006f};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      // Whole rows of unit normals (the fast path) and rows with every kind of pixel.
      const float len = y % 3 == 0 ? 1.0f : lengths[rng() % (sizeof lengths / sizeof lengths[0])];
      const float a = float(rng() % 628) * 0.01f, z = float(rng() % 200) * 0.01f - 1.0f, r = std::sqrt(1 - z * z);
      float n[3] = {len * r * std::cos(a), len * r * std::sin(a), len * z};
      if (rng() % 17 == 0) n[rng() % 3] = awkwardValue(rng);
      for (int c = 0; c < 3; ++c) {
        f[Buffer::Normal].at(x, y, c) = n[c];
        const float e = rng() % 4 == 0 ? awkwardValue(rng) : float(rng() % 5) * 0.25f;
        f[Buffer::Emission].at(x, y, c) = e;
        // colour equal to, above, below the emission, or awkward
        const int kind = int(rng() % 4);
        f[Buffer::Color].at(x, y, c) = kind == 0 ? e : kind == 1 ? e + 0.5f : kind == 2 ? e * 0.5f : awkwardValue(rng);
      }
    }
  const FrameInputs in = f.inputs();
  // The scalar rules, one after the other.
  SanitizeStats expect{};
  auto sanitized = [&](Buffer b, int x, int y, int c) {
    const ValueRange r = importRange(b);
    return Bounds{r.lo, r.hi}.sanitize(f[b].at(x, y, c), expect[size_t(b)]);
  };
  Image wantNormal(w, h, 3), wantColor(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float n[3], e[3];
      for (int c = 0; c < 3; ++c) {
        n[c] = sanitized(Buffer::Normal, x, y, c);
        e[c] = sanitized(Buffer::Emission, x, y, c);
        wantColor.at(x, y, c) = std::max(0.0f, flushTiny(sanitized(Buffer::Color, x, y, c) - e[c]));
      }
      expect[size_t(Buffer::Normal)].renormalized += renormalize(n[0], n[1], n[2]);
      for (int c = 0; c < 3; ++c) wantNormal.at(x, y, c) = n[c];
    }
  ASSERT_GT(expect[size_t(Buffer::Normal)].renormalized, 20u);  // the input exercises it
  for (CpuPath p : supportedCpuPaths()) {
    ScopedCpuPath force(p);
    FrameData d;
    SanitizeStats counts{};
    importFrame(in, {Buffer::Color}, d, nullptr, &counts);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 3; ++c) {
          ASSERT_EQ(std::bit_cast<uint32_t>(d.plane(Buffer::Normal, c)(x, y)), std::bit_cast<uint32_t>(wantNormal.at(x, y, c)))
              << cpuPathName(p) << " normal " << x << "," << y << "," << c;
          ASSERT_EQ(std::bit_cast<uint32_t>(d.plane(Buffer::Color, c)(x, y)), std::bit_cast<uint32_t>(wantColor.at(x, y, c)))
              << cpuPathName(p) << " color " << x << "," << y << "," << c;
        }
    for (Buffer b : {Buffer::Color, Buffer::Normal, Buffer::Emission}) {
      EXPECT_EQ(counts[size_t(b)].nonFinite, expect[size_t(b)].nonFinite) << cpuPathName(p) << " " << bufferName(b);
      EXPECT_EQ(counts[size_t(b)].outOfRange, expect[size_t(b)].outOfRange) << cpuPathName(p) << " " << bufferName(b);
      EXPECT_EQ(counts[size_t(b)].renormalized, expect[size_t(b)].renormalized) << cpuPathName(p) << " " << bufferName(b);
    }
  }
}

// Every combination of tap tests the vector paths compile separately (depth, normal, object
// id, position: template arguments of TapTest::bilinear8) against the scalar tests.
// Widths 83 and 96: a row ending in the scalar tail, and one whose last vector group ends at the
// border (its one-sided depth slope and other-side position footprint, as the first group's).
TEST(CpuPath, ReprojectionTapsAreTheSameOnEveryPath) {
  for (const int width : {83, 96}) {
    SCOPED_TRACE("width " + std::to_string(width));
    synthetic::Scene scene;
    scene.width = width;
    scene.height = 47;
    const Frame f0 = synthetic::makeFrame(scene, 0), f1 = synthetic::makeFrame(scene, 1);
    FrameData d0, d1;
    importFrame(f0.inputs(), {Buffer::Color}, d0);
    importFrame(f1.inputs(), {Buffer::Color}, d1);
    ASSERT_TRUE(d1.has(Buffer::Position) && d1.has(Buffer::ObjectId) && !d1.has(Buffer::DepthGradient));
    struct Case {
      const char* name;
      ReprojectionSettings settings;
      bool normals = true;
      bool depthGradient = false;  // the frame's own slope planes instead of neighbour differences
    };
    std::vector<Case> cases;
    cases.push_back({"defaults (depth, normal, id)", {}});
    cases.push_back({"defaults, depth gradient given", {}, true, true});
    cases.push_back({"BMFR (normal, position)", BmfrSettings{}.reprojection});
    Case all{"depth, normal, id, position", {}};
    all.settings.positionFootprints = 4.0f;
    cases.push_back(all);
    Case tight{"normal, position within half a footprint (rejects taps)", BmfrSettings{}.reprojection};
    tight.settings.positionFootprints = 0.5f;
    cases.push_back(tight);
    Case depthOnly{"depth", {}, false};
    depthOnly.settings.testObjectId = false;
    cases.push_back(depthOnly);
    Case idOnly{"id", {}, false};
    idOnly.settings.testDepth = false;
    cases.push_back(idOnly);
    Case none{"no test", {}, false};
    none.settings.testDepth = none.settings.testObjectId = false;
    cases.push_back(none);
    for (Case& c : cases) {
      c.settings.fallback3x3 = true;
      FrameData cur = d1, prev = d0;
      if (!c.normals) cur.buffers[int(Buffer::Normal)].clear(), prev.buffers[int(Buffer::Normal)].clear();
      if (c.depthGradient) {
        // Central differences of the depth, halved at the borders' one-sided ends.
        const Plane& z = cur.plane(Buffer::Depth);
        Plane gx(z.width, z.height), gy(z.width, z.height);
        for (int y = 0; y < z.height; ++y)
          for (int x = 0; x < z.width; ++x) {
            gx(x, y) = 0.5f * (z(std::min(x + 1, z.width - 1), y) - z(std::max(x - 1, 0), y));
            gy(x, y) = 0.5f * (z(x, std::min(y + 1, z.height - 1)) - z(x, std::max(y - 1, 0)));
          }
        cur.buffers[int(Buffer::DepthGradient)] = {gx, gy};
      }
      Reprojection ref;
      {
        ScopedCpuPath force(CpuPath::Sse2);  // the scalar tap tests
        reproject(cur, &prev, c.settings, ref);
      }
      const auto counts = ref.counts();
      EXPECT_GT(counts[Reprojection::Bilinear], size_t(scene.width * scene.height / 2)) << c.name;
      for (CpuPath p : supportedCpuPaths()) {
        ScopedCpuPath force(p);
        Reprojection rp;
        reproject(cur, &prev, c.settings, rp);
        for (size_t i = 0; i < rp.kind.size(); ++i) {
          ASSERT_EQ(rp.kind[i], ref.kind[i]) << c.name << ", " << cpuPathName(p) << " pixel " << i;
          if (rp.kind[i] == Reprojection::None) continue;
          ASSERT_EQ(rp.base[i], ref.base[i]) << c.name << ", " << cpuPathName(p) << " pixel " << i;
          for (int t = 0; t < 4; ++t)
            ASSERT_NEAR(rp.weights[i][t], ref.weights[i][t], 1e-6f) << c.name << ", " << cpuPathName(p) << " pixel " << i;
        }
      }
    }
  }
}

// The tolerances at a row's ends take the one-sided neighbours of the scalar tests: the depth
// slope the pixel itself (a slope of 0 there), the position footprint the neighbour on the other
// side. Depth ramps by 0.01 a column, the previous frame 0.005 deeper at the same texels, and
// the motion moves the footprints 0.3 right in the left half and 0.3 left in the right one (so
// both row ends' footprints lie inside and their groups take the vector path). With only the
// slope term (2 x 0.01) every interior pixel keeps both taps and the two end pixels keep none.
// Positions 0.01 apart along x, the previous 0.004 further, with a tolerance of one footprint:
// every pixel keeps a tap, the end pixels too. (A vector lane that keeps no tap is redone by the
// scalar test, so of the two conventions only a too-wide tolerance, the depth case's, could
// change the record; the position case checks the result.) Width 96, a multiple of every
// path's group. On every path.
TEST(CpuPath, ReprojectionRowEndsTakeTheScalarTestsOneSidedNeighbours) {
  const int w = 96, h = 6;
  for (const bool position : {false, true}) {
    SCOPED_TRACE(position ? "position footprint" : "depth slope");
    FrameData prev, cur;
    for (FrameData* f : {&prev, &cur}) {
      f->width = w, f->height = h;
      f->buffers[int(Buffer::Depth)] = {Plane(w, h)};
      f->buffers[int(Buffer::Normal)] = {Plane(w, h), Plane(w, h), Plane(w, h)};
      f->buffers[int(Buffer::Position)] = {Plane(w, h), Plane(w, h), Plane(w, h)};
    }
    cur.buffers[int(Buffer::Motion)] = {Plane(w, h), Plane(w, h)};
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        cur.plane(Buffer::Depth)(x, y) = 1.0f + 0.01f * float(x);
        prev.plane(Buffer::Depth)(x, y) = cur.plane(Buffer::Depth)(x, y) + 0.005f;
        cur.plane(Buffer::Position, 0)(x, y) = 0.01f * float(x);
        prev.plane(Buffer::Position, 0)(x, y) = 0.01f * float(x) + 0.004f;
        cur.plane(Buffer::Position, 1)(x, y) = prev.plane(Buffer::Position, 1)(x, y) = 1e-4f * float(y);
        cur.plane(Buffer::Normal, 2)(x, y) = prev.plane(Buffer::Normal, 2)(x, y) = 1.0f;
        cur.plane(Buffer::Motion, 0)(x, y) = x < w / 2 ? 0.3f : -0.3f;
      }
    ReprojectionSettings s;
    s.fallback3x3 = false;
    if (position) {
      s.testDepth = false;
      s.positionFootprints = 1.0f;
    } else {
      s.depthTolerance = 0.0f;  // the slope term alone
    }
    for (CpuPath p : supportedCpuPaths()) {
      ScopedCpuPath force(p);
      Reprojection rp;
      reproject(cur, &prev, s, rp);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const bool end = x == 0 || x == w - 1;
          const auto want = !position && end ? Reprojection::None : Reprojection::Bilinear;
          ASSERT_EQ(rp.kind[size_t(y) * w + x], want) << cpuPathName(p) << " pixel " << x << "," << y;
        }
    }
  }
}

// The vector paths read a group's bilinear taps with vector loads where the footprints are
// consecutive, as selections between loads of two or three rows where each lane's footprint
// starts at most one column right of consecutive and at most one row lower (smooth motion),
// and with gathers otherwise. Four motion fields make each layout the common case (classified
// here, groups of eight); every previous texel passes the current pixels' depth, normal and id
// tests or fails them at random, so a tap read from a wrong texel changes which taps are
// accepted. On every path the record equals the sse2 path's (scalar taps).
TEST(CpuPath, ReprojectionTapsOfEveryGroupLayoutAreTheSameOnEveryPath) {
  const int w = 101, h = 23;
  enum Field { Uniform, Stepped, Straddling, Scattered };
  for (const Field field : {Uniform, Stepped, Straddling, Scattered}) {
    SCOPED_TRACE("motion field " + std::to_string(int(field)));
    std::mt19937 rng(17u + unsigned(field));
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    FrameData prev, cur;
    for (FrameData* f : {&prev, &cur}) {
      f->width = w, f->height = h;
      f->buffers[int(Buffer::Depth)] = {Plane(w, h)};
      f->buffers[int(Buffer::Normal)] = {Plane(w, h), Plane(w, h), Plane(w, h)};
      f->buffers[int(Buffer::ObjectId)] = {Plane(w, h)};
    }
    cur.buffers[int(Buffer::Motion)] = {Plane(w, h), Plane(w, h)};
    int fx[w], fy[w];
    size_t layouts[4] = {};
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        prev.plane(Buffer::Depth)(x, y) = 1.0f + u(rng);  // within 0.25 of the current 1.5: half
        const bool facing = u(rng) < 0.8f;
        prev.plane(Buffer::Normal, facing ? 2 : 0)(x, y) = 1.0f;
        prev.plane(Buffer::ObjectId)(x, y) = u(rng) < 0.9f ? 3.0f : 4.0f;
        cur.plane(Buffer::Depth)(x, y) = 1.5f;
        cur.plane(Buffer::Normal, 2)(x, y) = 1.0f;
        cur.plane(Buffer::ObjectId)(x, y) = 3.0f;
        float dx = 2.3f, dy = -0.6f;                      // Uniform: consecutive groups
        if (field == Stepped) dx += 0.11f * float(x);      // a one-column step every ~9 pixels
        if (field == Straddling) dx = 1.0f + 1e-4f * (u(rng) - 0.5f), dy = -1.0f + 1e-4f * (u(rng) - 0.5f);
        if (field == Scattered) dx = 16.0f * u(rng) - 8.0f, dy = 16.0f * u(rng) - 8.0f;
        cur.plane(Buffer::Motion, 0)(x, y) = dx;
        cur.plane(Buffer::Motion, 1)(x, y) = dy;
        fx[x] = int(std::floor(float(x) + dx)), fy[x] = int(std::floor(float(y) + dy));
      }
      for (int x = 0; x + 8 <= w; x += 8) {
        bool inside = true, consecutive = true;
        int shiftMin = fx[x], shiftMax = fx[x], topMin = fy[x], topMax = fy[x];
        for (int k = 0; k < 8; ++k) {
          inside = inside && fx[x + k] >= 0 && fy[x + k] >= 0 && fx[x + k] < w - 1 && fy[x + k] < h - 1;
          consecutive = consecutive && fy[x + k] == fy[x] && fx[x + k] == fx[x] + k;
          shiftMin = std::min(shiftMin, fx[x + k] - k), shiftMax = std::max(shiftMax, fx[x + k] - k);
          topMin = std::min(topMin, fy[x + k]), topMax = std::max(topMax, fy[x + k]);
        }
        if (!inside) continue;
        const bool window = shiftMax - shiftMin <= 1 && topMax - topMin <= 1;
        ++layouts[consecutive ? Uniform : window ? (topMax == topMin ? Stepped : Straddling) : Scattered];
      }
    }
    const size_t groups = layouts[0] + layouts[1] + layouts[2] + layouts[3];
    ASSERT_GT(layouts[field], groups / 2) << layouts[0] << " " << layouts[1] << " " << layouts[2] << " " << layouts[3];
    ReprojectionSettings s;
    s.depthTolerance = 0.25f / 1.5f;
    Reprojection ref;
    {
      ScopedCpuPath force(CpuPath::Sse2);
      reproject(cur, &prev, s, ref);
    }
    const auto counts = ref.counts();
    EXPECT_GT(counts[Reprojection::Bilinear], size_t(w * h / 4));
    for (CpuPath p : supportedCpuPaths()) {
      ScopedCpuPath force(p);
      Reprojection rp;
      reproject(cur, &prev, s, rp);
      for (size_t i = 0; i < rp.kind.size(); ++i) {
        ASSERT_EQ(rp.kind[i], ref.kind[i]) << cpuPathName(p) << " pixel " << i;
        if (rp.kind[i] == Reprojection::None) continue;
        ASSERT_EQ(rp.base[i], ref.base[i]) << cpuPathName(p) << " pixel " << i;
        for (int t = 0; t < 4; ++t) ASSERT_NEAR(rp.weights[i][t], ref.weights[i][t], 1e-6f) << cpuPathName(p) << " pixel " << i;
      }
    }
  }
}

// Output of `frames` frames of the synthetic scene with a method on the current path.
Image runMethod(const std::string& method, const std::vector<std::pair<std::string, std::string>>& settings, int frames) {
  synthetic::Scene scene;
  scene.width = 99;
  scene.height = 61;
  auto d = Device::create({.backend = Backend::Cpu, .threads = 2})->createDenoiser(method);
  for (const auto& [k, v] : settings) d->set(k, v);
  Image out(scene.width, scene.height, 3);
  for (int t = 0; t < frames; ++t) d->denoise(synthetic::makeFrame(scene, t).inputs(), out.view());
  return out;
}

TEST(CpuPath, WholeMethodsAgreeWithTheSse2PathOnEveryPath) {
  struct Case {
    std::string method;
    std::vector<std::pair<std::string, std::string>> settings;
    double tolerance;  // max |difference| / max |sse2 output|
  };
  // The paths differ in rounding only: FMA contraction (avx2, avx512) and the reciprocal
  // estimate's precision (rcp 12 bits, rcp14 14 bits, each refined by one Newton step); the
  // a-trous filter's 4, 8 or 16 pixels per iteration do not change the order of its sums.
  // Measured on the Sapphire Rapids Xeon over 8 frames (max |difference| / max |output|, as
  // the test's properties record): accumulate 1.5e-7, svgf 3.3e-7, dundr 4.1e-7, bmfr 6.8e-7
  // (the QR amplifies rounding by the blocks' condition); the tolerances leave 7-30x margin.
  const std::vector<Case> cases = {{"accumulate", {}, 1e-6},
                                   {"svgf", {}, 1e-5},
                                   {"svgf", {{"variant", "dundr"}}, 1e-5},
                                   {"bmfr", {{"positionTolerance", "0.3"}}, 2e-5}};
  for (const Case& c : cases) {
    Image ref;
    {
      ScopedCpuPath force(CpuPath::Sse2);
      ref = runMethod(c.method, c.settings, 8);
    }
    float scale = 0;
    for (float v : ref.pixels) scale = std::max(scale, std::abs(v));
    ASSERT_GT(scale, 0.0f);
    for (CpuPath p : supportedCpuPaths()) {
      if (p == CpuPath::Sse2) continue;
      ScopedCpuPath force(p);
      const Image out = runMethod(c.method, c.settings, 8);
      double maxDiff = 0;
      for (size_t i = 0; i < out.pixels.size(); ++i) maxDiff = std::max(maxDiff, double(std::abs(out.pixels[i] - ref.pixels[i])));
      EXPECT_LE(maxDiff / scale, c.tolerance) << c.method << (c.settings.empty() ? "" : " " + c.settings[0].second)
                                              << " on " << cpuPathName(p);
      char measured[32];
      std::snprintf(measured, sizeof measured, "%.2e", maxDiff / scale);
      RecordProperty(c.method + (c.settings.empty() ? "" : "_" + c.settings[0].second) + "_" + cpuPathName(p), measured);
    }
  }
}

}  // namespace
}  // namespace rtd
