// The renderer's reflection features (Voorhuis Sec. 4; checklist items 4 and 15): written for
// every pixel of roughness below 0.4, through chains of mirrors to the first non-mirror hit,
// and the ray-differential footprint there, checked against finite differences of the
// neighbouring pixels' traced hits.
#ifdef HAVE_RTDENOISE_RENDER
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "render/render_test_util.h"

namespace rtd::render::test {
namespace {

double dist(const Vec& a, const Vec& b) { return std::sqrt(dot(sub(a, b), sub(a, b))); }

// A glossy floor (roughness 0.2) reflects a vertical quad: its pixels carry the features of
// the quad point the perfect mirror ray hits, as a mirror's would.
TEST(ReflectionFeatures, GlossyPixelsBelowThresholdFollowTheMirrorRay) {
  auto scene = sceneFromJson(R"({
    "objects": [
      {"shape": "quad", "scale": 40, "material": {"baseColor": [0.9, 0.9, 0.9], "metallic": 1, "roughness": 0.2}},
      {"shape": "quad", "translation": [0, 1, -3], "rotation": [90, 0, 0], "scale": [4, 1, 2],
       "material": {"baseColor": [0.2, 0.5, 0.7], "roughness": 1, "specular": 0}}
    ],
    "sky": {"color": 1}, "camera": {"position": [0, 1, 3], "target": [0, 0.2, -1], "fov": 60}
  })");
  const int w = 32, h = 24;
  Renderer r(scene, tiny(w, h));
  const Frame f = r.render(0);
  int quadHits = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (f[Buffer::ObjectId].at(x, y) != 1.0f) continue;
      const Vec p = px3(f[Buffer::Position], x, y);
      const Vec refl = px3(f[Buffer::MirrorDirection], x, y);
      const double t = refl[2] < 0 ? (-3 - p[2]) / refl[2] : -1;
      const Vec q = {p[0] + t * refl[0], p[1] + t * refl[1], p[2] + t * refl[2]};
      if (!(t > 0 && std::fabs(q[0]) < 1.9 && q[1] > 0.05 && q[1] < 1.95)) continue;
      ++quadHits;
      EXPECT_LT(dist(px3(f[Buffer::ReflectedPosition], x, y), q), 2e-3);
      EXPECT_NEAR(f[Buffer::ReflectedAlbedo].at(x, y, 1), 0.5, 1e-6);
      EXPECT_GT(f[Buffer::ReflectedFootprint].at(x, y), 0.0f);
    }
  EXPECT_GT(quadHits, 60);
}

// Two parallel vertical mirrors facing each other; the camera looks at one through the gap:
// rays bounce between them until they reach the diffuse floor. The reflected features are
// those of the floor point the mirror chain reaches, computed here by unfolding the chain.
TEST(ReflectionFeatures, StackedMirrorsResolveToTheFirstDiffuseVertex) {
  auto scene = sceneFromJson(R"({
    "objects": [
      {"shape": "quad", "scale": 40, "material": {"baseColor": [0.3, 0.6, 0.2], "roughness": 1, "specular": 0}},
      {"shape": "quad", "translation": [-1, 2, 0], "rotation": [0, 0, -90], "scale": [4, 1, 8], "material": {"mirror": true}},
      {"shape": "quad", "translation": [1, 2, 0], "rotation": [0, 0, 90], "scale": [4, 1, 8], "material": {"mirror": true}}
    ],
    "sky": {"color": 1}, "camera": {"position": [0.3, 3, 3], "target": [-1, 1.2, -1], "fov": 40}
  })");
  const int w = 24, h = 24;
  Renderer r(scene, tiny(w, h));
  const Frame f = r.render(0);
  int chains = 0, multi = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (f[Buffer::Metalness].at(x, y) != 1.0f) continue;  // a mirror pixel
      // Unfold: walk the mirror ray between the planes x = -1 and x = +1 down to the floor.
      Vec o = px3(f[Buffer::Position], x, y), d = px3(f[Buffer::MirrorDirection], x, y);
      int bounces = 1;
      bool floor = false;
      for (int k = 0; k < 6; ++k) {
        const double tFloor = d[1] < 0 ? -o[1] / d[1] : 1e30;
        const double tWall = d[0] > 0 ? (1 - o[0]) / d[0] : d[0] < 0 ? (-1 - o[0]) / d[0] : 1e30;
        if (tFloor < tWall) {
          o = {o[0] + tFloor * d[0], 0, o[2] + tFloor * d[2]};
          floor = true;
          break;
        }
        o = {o[0] + tWall * d[0], o[1] + tWall * d[1], o[2] + tWall * d[2]};
        if (o[1] > 3.9 || std::fabs(o[2]) > 3.9) break;  // past a mirror's edge
        d[0] = -d[0];
        ++bounces;
      }
      // Keep clear of the mirrors' feet, where the last bounce is ambiguous.
      if (!floor || std::fabs(o[0]) > 0.95) continue;
      ++chains;
      multi += bounces >= 2;
      EXPECT_LT(dist(px3(f[Buffer::ReflectedPosition], x, y), o), 5e-3) << x << "," << y << " bounces " << bounces;
      EXPECT_NEAR(f[Buffer::ReflectedAlbedo].at(x, y, 1), 0.6, 1e-6);
    }
  EXPECT_GT(multi, 10);
  EXPECT_GT(chains, 20);
}

// The footprint at the reflected hit, (|dP/dx| + |dP/dy|) / 2, equals its central
// differences over the neighbouring pixels' traced reflected points (where all lie on one
// smooth surface): for a flat mirror and for a mirror sphere (whose curvature spreads the rays).
TEST(ReflectionFeatures, FootprintMatchesFiniteDifferencesOfNeighbouringHits) {
  for (const char* mirror : {R"({"shape": "quad", "scale": 40, "material": {"mirror": true}})",
                             R"({"shape": "sphere", "translation": [0, 1, 0], "scale": 1.6, "material": {"mirror": true}})"}) {
    auto scene = sceneFromJson(std::string(R"({"objects": [)") + mirror + R"(,
        {"shape": "quad", "translation": [0, 2, -4], "rotation": [90, 0, 0], "scale": [40, 1, 40],
         "material": {"baseColor": [0.5, 0.5, 0.5], "roughness": 1, "specular": 0}},
        {"shape": "quad", "translation": [0, 2, 6], "rotation": [-90, 0, 0], "scale": [40, 1, 40],
         "material": {"baseColor": [0.5, 0.5, 0.5], "roughness": 1, "specular": 0}}],
      "sky": {"color": 1}, "camera": {"position": [0, 1.2, 4], "target": [0, 0.9, 0], "fov": 40}})");
    const int w = 96, h = 72;
    Renderer r(scene, tiny(w, h));
    const Frame f = r.render(0);
    std::vector<double> rel;
    for (int y = 1; y + 1 < h; ++y)
      for (int x = 1; x + 1 < w; ++x) {
        auto isMirror = [&](int u, int v) { return f[Buffer::Metalness].at(u, v) == 1.0f && f[Buffer::ReflectedFootprint].at(u, v) > 0; };
        if (!isMirror(x, y) || !isMirror(x + 1, y) || !isMirror(x, y + 1) || !isMirror(x - 1, y) || !isMirror(x, y - 1)) continue;
        const Vec nc = px3(f[Buffer::ReflectedNormal], x, y);
        bool same = true;
        for (auto [u, v] : {std::pair{x + 1, y}, {x - 1, y}, {x, y + 1}, {x, y - 1}})
          same &= dist(px3(f[Buffer::ReflectedNormal], u, v), nc) < 1e-3;
        if (!same) continue;
        // Central differences (second-order accurate, as the analytic derivative).
        const double fd = 0.25 * (dist(px3(f[Buffer::ReflectedPosition], x + 1, y), px3(f[Buffer::ReflectedPosition], x - 1, y)) +
                                  dist(px3(f[Buffer::ReflectedPosition], x, y + 1), px3(f[Buffer::ReflectedPosition], x, y - 1)));
        rel.push_back(std::fabs(f[Buffer::ReflectedFootprint].at(x, y) - fd) / fd);
      }
    ASSERT_GT(rel.size(), 40u) << mirror;
    std::sort(rel.begin(), rel.end());
    // The median: central differences carry a second-order error on the sphere's diverging
    // reflection (1.1% at twice this resolution, 4.6% at half) and jump across its facets.
    EXPECT_LT(rel[rel.size() / 2], 0.04) << mirror;
  }
}

}  // namespace
}  // namespace rtd::render::test
#endif
