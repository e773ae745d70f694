// Voorhuis' diamond search (Algorithm 1), its subpixel refinement (Eqs. 2-3, and the quadratic
// fit that is the default) and the distance functions (Eqs. 1, 4, 5) on synthetic fields with
// known answers.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "passes/diamond_search.h"

namespace rtd {
namespace {

// A smooth injective "previous world position" field: a near-isotropic linear map plus a
// gentle bend, so the distance to any of its points has a single minimum over the image and
// no diagonal valley that axis-aligned diamond steps could stall in.
struct Field {
  int w, h;
  double ox = 0, oy = 0;  // sub-pixel shift of the current pixel's point
  void at(double x, double y, float out[3]) const {
    out[0] = float(0.1 * x + 0.01 * y + 1e-4 * x * x);
    out[1] = float(0.1 * y - 0.01 * x);
    out[2] = float(1e-4 * x * y);
  }
};

TEST(DiamondSearch, FindsExactIntegerOffsetOnShiftedField) {
  const Field f{160, 120};
  for (bool scale : {true, false}) {
    // The previous frame holds the field; the current pixel p shows the point the previous
    // frame had at p + (13, -7): its reflection moved by (-13, +7), MV (prev - cur) = (13, -7).
    const int px = 60, py = 70, dx = 13, dy = -7;
    float wp[3];
    f.at(px + dx, py + dy, wp);
    auto dist = [&](int qx, int qy) {
      float wq[3];
      f.at(qx, qy, wq);
      return worldDistance(wp, wq);
    };
    DiamondSearchOptions opt;
    opt.scaleLdsp = scale;
    const SearchResult r = diamondSearch(px, py, px + 0.5f, py + 0.5f, f.w, f.h, dist, opt);
    ASSERT_TRUE(r.found());
    // The 5-tap LDSP moves by even steps and the SDSP once by one pixel, so an offset with
    // two odd components ends a diagonal neighbour away; the subpixel step (Eqs. 2-3) then
    // sees the zero distance in the 3x3 around it and returns exactly that pixel's centre.
    EXPECT_LE(std::abs(r.bestX - (px + dx)) + std::abs(r.bestY - (py + dy)), 2) << "scaleLdsp " << scale;
    EXPECT_EQ(r.matchX - (px + 0.5f), float(dx)) << "scaleLdsp " << scale;
    EXPECT_EQ(r.matchY - (py + 0.5f), float(dy));
  }
}

TEST(DiamondSearch, SecondStartFromPrimaryMotionIsUsed) {
  // The primary MV points 50 px away, next to the true match: the search starts there.
  const Field f{200, 100};
  const int px = 20, py = 50;
  float wp[3];
  f.at(px + 51, py, wp);
  int evaluated = 0;
  auto dist = [&](int qx, int qy) {
    ++evaluated;
    float wq[3];
    f.at(qx, qy, wq);
    return worldDistance(wp, wq);
  };
  DiamondSearchOptions opt;
  opt.subpixel = false;
  const SearchResult r = diamondSearch(px, py, px + 50.5f, py + 0.5f, f.w, f.h, dist, opt);
  EXPECT_EQ(r.bestX, px + 51);
  EXPECT_EQ(r.bestY, py);
  EXPECT_LT(r.taps, 40);  // a few steps from the second start, not a 50 px walk
  EXPECT_EQ(r.taps, evaluated);
}

TEST(DiamondSearch, TapCountOfAStaticPixel) {
  // Best match at p itself and a zero primary MV (one start): LDSP at step 4, 2, 1 (4 taps
  // each, no improvement), then the SDSP (4): 1 + 12 + 4 = 17 evaluations; plus the 8
  // neighbours scored by the subpixel step. Without LDSP scaling: 1 + 4 + 4 = 9.
  const Field f{64, 64};
  float wp[3];
  f.at(30, 30, wp);
  auto dist = [&](int qx, int qy) {
    float wq[3];
    f.at(qx, qy, wq);
    return worldDistance(wp, wq);
  };
  DiamondSearchOptions opt;
  opt.subpixel = false;
  EXPECT_EQ(diamondSearch(30, 30, 30.5f, 30.5f, 64, 64, dist, opt).taps, 17);
  opt.subpixel = true;
  EXPECT_EQ(diamondSearch(30, 30, 30.5f, 30.5f, 64, 64, dist, opt).taps, 25);
  opt.scaleLdsp = false;
  opt.subpixel = false;
  EXPECT_EQ(diamondSearch(30, 30, 30.5f, 30.5f, 64, 64, dist, opt).taps, 9);
}

TEST(DiamondSearch, LdspScalingCoversLargeMotionInFewerTaps) {
  const Field f{256, 64};
  const int px = 20, py = 32;
  float wp[3];
  f.at(px + 60, py + 3, wp);
  auto dist = [&](int qx, int qy) {
    float wq[3];
    f.at(qx, qy, wq);
    return worldDistance(wp, wq);
  };
  DiamondSearchOptions on, off;
  off.scaleLdsp = false;
  const SearchResult a = diamondSearch(px, py, px + 0.5f, py + 0.5f, f.w, f.h, dist, on);
  const SearchResult b = diamondSearch(px, py, px + 0.5f, py + 0.5f, f.w, f.h, dist, off);
  for (const SearchResult* r : {&a, &b}) {
    EXPECT_EQ(r->matchX, px + 60.5f);
    EXPECT_EQ(r->matchY, py + 3.5f);
  }
  EXPECT_LT(a.taps, b.taps);
}

TEST(DiamondSearch, LocalMinimumAndBruteForce) {
  // Two wells: a shallow one near p and the true match 30 px away behind a ridge. The search
  // with a 4-2-1 step from p can be trapped; the brute-force 200x200 window never is.
  const int w = 120, h = 60, px = 40, py = 30;
  auto dist = [&](int qx, int qy) {
    const float a = std::hypot(float(qx - (px + 3)), float(qy - py)) + 5.0f;   // local, value >= 5
    const float b = std::hypot(float(qx - (px + 30)), float(qy - py)) * 0.5f;  // global, 0 at +30
    return std::min(a, b);
  };
  const SearchResult ds = diamondSearch(px, py, px + 0.5f, py + 0.5f, w, h, dist);
  EXPECT_EQ(ds.bestX, px + 3);  // trapped in the shallow well, as Sec. 7.4 describes
  const SearchResult bf = bruteForceSearch(px, py, w, h, dist);
  EXPECT_EQ(bf.bestX, px + 30);
  EXPECT_EQ(bf.bestDistance, 0.0f);
  EXPECT_GE(bf.taps, 120 * 60);  // the whole (clipped) window plus the refinement
}

TEST(DiamondSearch, TapsOutsideTheImageOrWithoutMatchAreSkipped) {
  const int w = 16, h = 16;
  // Only the left column can match; the best is at its top.
  auto dist = [&](int qx, int qy) { return qx == 0 ? float(qy) + 1.0f : kNoMatch; };
  const SearchResult r = diamondSearch(0, 3, 0.5f, 3.5f, w, h, dist);
  ASSERT_TRUE(r.found());
  EXPECT_EQ(r.bestX, 0);
  EXPECT_EQ(r.bestY, 0);
  // Nothing matches anywhere: no result.
  const SearchResult none = diamondSearch(5, 5, 5.5f, 5.5f, w, h, [](int, int) { return kNoMatch; });
  EXPECT_FALSE(none.found());
}

// ---- Eqs. 2-3 ----

struct Grid {
  float d[9];  // distances of the 3x3 around the best match at (5, 5)
  float operator()(int x, int y) const { return d[(y - 4) * 3 + (x - 4)]; }
};

SearchResult refine(const Grid& g) {
  SearchResult r;
  r.bestX = r.bestY = 5;
  r.bestDistance = g(5, 5);
  auto score = [&](int x, int y) { return g(x, y); };
  subpixelRefine(score, r, SubpixelFit::inverseDistance);
  return r;
}

TEST(SubpixelRefinement, ZeroDistanceGivesThatCoordinate) {
  const SearchResult r = refine({{3, 2, 3, 2, 0, 1, 3, 2, 3}});
  EXPECT_EQ(r.matchX, 5.5f);
  EXPECT_EQ(r.matchY, 5.5f);
}

TEST(SubpixelRefinement, WeightsAreProductsOfTheOtherDistances) {
  // Best block: (5,5),(6,5),(5,6),(6,6) with distances 1, 2, 2, 4 (sum 9, the smallest).
  const SearchResult r = refine({{9, 9, 9, 9, 1, 2, 9, 2, 4}});
  const double w[4] = {2 * 2 * 4, 1 * 2 * 4, 1 * 2 * 4, 1 * 2 * 2};  // Eq. 2
  const double cx[4] = {5.5, 6.5, 5.5, 6.5}, cy[4] = {5.5, 5.5, 6.5, 6.5};
  double sw = 0, sx = 0, sy = 0;
  for (int k = 0; k < 4; ++k) sw += w[k], sx += w[k] * cx[k], sy += w[k] * cy[k];
  EXPECT_NEAR(r.matchX, sx / sw, 1e-6);  // Eq. 3
  EXPECT_NEAR(r.matchY, sy / sw, 1e-6);
}

TEST(SubpixelRefinement, TwoZeroDistancesDoNotDivideByZero) {
  const SearchResult r = refine({{9, 9, 9, 9, 0, 0, 9, 3, 3}});
  EXPECT_TRUE(std::isfinite(r.matchX));
  EXPECT_NEAR(r.matchX, 6.0, 1e-6);  // the mean of the two zero-distance pixels
  EXPECT_NEAR(r.matchY, 5.5, 1e-6);
}

TEST(SubpixelRefinement, LinearRampFollowsFractionalOffsetMonotonically) {
  // Previous world = linear ramp of the pixel coordinate; the current point lies at
  // p + (3 + t, -2 + t/2): the match stays inside the chosen 2x2 block and moves with t.
  const int w = 32, h = 32, px = 10, py = 16;
  float lastX = -1, lastY = -1;
  for (int k = 0; k <= 8; ++k) {
    const float t = 0.05f + 0.1f * k;
    const float wp[3] = {0.2f * (px + 3 + t), 0.2f * (py - 2 + 0.5f * t), 0.0f};
    auto dist = [&](int qx, int qy) {
      const float wq[3] = {0.2f * qx, 0.2f * qy, 0.0f};
      return worldDistance(wp, wq);
    };
    const SearchResult r = diamondSearch(px, py, px + 0.5f, py + 0.5f, w, h, dist);
    ASSERT_TRUE(r.found());
    const float mx = r.matchX - 0.5f, my = r.matchY - 0.5f;  // in pixel-index units
    EXPECT_GE(mx, float(px + 3) - 1e-4f);
    EXPECT_LE(mx, float(px + 4) + 1e-4f);
    EXPECT_GE(my, float(py - 2) - 1e-4f);
    EXPECT_LE(my, float(py - 1) + 1e-4f);
    EXPECT_GT(mx, lastX);
    EXPECT_GE(my, lastY);
    lastX = mx;
    lastY = my;
  }
}

// SubpixelFit::quadratic: on a linear ramp (the squared distance is then exactly a quadratic)
// the match is the true fractional position, where Eqs. 2-3 are pulled towards the centre of
// their 2x2 block; off the image or with a tap that cannot match it falls back to Eqs. 2-3.
TEST(SubpixelRefinement, QuadraticFitIsExactOnALinearRampWhereEqs23AreBiased) {
  const int w = 32, h = 32, px = 10, py = 16;
  double worstQuadratic = 0, worstEq23 = 0;
  for (int k = 0; k <= 8; ++k) {
    const float t = 0.05f + 0.1f * k;
    const float tx = px + 3 + t, ty = py - 2 + 0.5f * t;  // pixel-index units of the true point
    // An anisotropic ramp with a shear, as the reflection of a tilted plane.
    auto world = [](float x, float y, float out[3]) {
      out[0] = 0.2f * x + 0.05f * y;
      out[1] = 0.12f * y;
      out[2] = 0.03f * x;
    };
    float wp[3];
    world(tx, ty, wp);
    auto dist = [&](int qx, int qy) {
      float wq[3];
      world(float(qx), float(qy), wq);
      return worldDistance(wp, wq);
    };
    for (SubpixelFit fit : {SubpixelFit::quadratic, SubpixelFit::inverseDistance}) {
      DiamondSearchOptions opt;
      opt.fit = fit;
      const SearchResult r = diamondSearch(px, py, px + 0.5f, py + 0.5f, w, h, dist, opt);
      ASSERT_TRUE(r.found());
      const double e = std::hypot(r.matchX - 0.5 - tx, r.matchY - 0.5 - ty);
      double& worst = fit == SubpixelFit::quadratic ? worstQuadratic : worstEq23;
      worst = std::max(worst, e);
    }
  }
  EXPECT_LT(worstQuadratic, 1e-3);
  EXPECT_GT(worstEq23, 0.1);
  // A 3x3 with a tap that cannot match: Eqs. 2-3 over the blocks without it.
  SearchResult r;
  r.bestX = r.bestY = 5;
  r.bestDistance = 1;
  const float d[9] = {kNoMatch, 9, 9, 9, 1, 2, 9, 2, 4};
  auto score = [&](int x, int y) { return d[(y - 4) * 3 + (x - 4)]; };
  SearchResult eq23 = r;
  subpixelRefine(score, r, SubpixelFit::quadratic);
  subpixelRefine(score, eq23, SubpixelFit::inverseDistance);
  EXPECT_EQ(r.matchX, eq23.matchX);
  EXPECT_EQ(r.matchY, eq23.matchY);
}

// ---- Eqs. 4-5 ----

RepresentativeRay ray(float ox, float oy, float oz, float dx, float dy, float dz, float depth) {
  const float l = std::sqrt(dx * dx + dy * dy + dz * dz);
  return {{ox, oy, oz}, {dx / l, dy / l, dz / l}, depth};
}

TEST(GlossyDistance, ApproxHitIsOriginPlusDepthAlongTheMirrorDirection) {
  const RepresentativeRay r = ray(1, 2, 3, 0, 0, -1, 4);
  float x[3];
  approxHit(r, x);
  EXPECT_FLOAT_EQ(x[0], 1);
  EXPECT_FLOAT_EQ(x[1], 2);
  EXPECT_FLOAT_EQ(x[2], -1);
}

TEST(GlossyDistance, Eq5Properties) {
  const RepresentativeRay a = ray(0, 0, 0, 1, 1, 0, 3);
  EXPECT_NEAR(glossyDistance(a, a), 0.0f, 1e-6f);  // identical rays
  // Same line, other origin along it and another sample depth: 0.
  const RepresentativeRay b = ray(0.5f, 0.5f, 0, 1, 1, 0, 7);
  EXPECT_NEAR(glossyDistance(a, b), 0.0f, 1e-5f);
  EXPECT_NEAR(glossyDistance(b, a), 0.0f, 1e-5f);
  // A parallel ray offset by s perpendicular to d: s, whichever is nearer.
  const float s = 0.37f;
  const RepresentativeRay c = ray(0, 0, s, 1, 1, 0, 10);
  EXPECT_NEAR(glossyDistance(a, c), s, 1e-5f);
  EXPECT_NEAR(glossyDistance(c, a), s, 1e-5f);
  // Non-parallel rays: symmetric, and measured from the nearer sample's approx_hit.
  const RepresentativeRay d = ray(1, 0, 0, 0, 1, 0.2f, 2);
  const RepresentativeRay e = ray(0, 0, 0, 0.1f, 1, 0, 5);
  EXPECT_FLOAT_EQ(glossyDistance(d, e), glossyDistance(e, d));
  float x[3];
  approxHit(d, x);  // d is nearer: distance from x to e's line
  const float v[3] = {x[0] - e.o[0], x[1] - e.o[1], x[2] - e.o[2]};
  const float t = v[0] * e.d[0] + v[1] * e.d[1] + v[2] * e.d[2];
  const float perp[3] = {v[0] - t * e.d[0], v[1] - t * e.d[1], v[2] - t * e.d[2]};
  EXPECT_NEAR(glossyDistance(d, e), std::sqrt(perp[0] * perp[0] + perp[1] * perp[1] + perp[2] * perp[2]), 1e-5f);
}

TEST(GlossyDistance, RayDistanceIsEq5InFrontOfTheFarOriginAndTheOriginDistanceBehindIt) {
  // The reference's distance (the text's "ray"): the far ray r_far from the origin along +x,
  // depth 10. A near sample whose approx_hit lies in front of r_far's origin: Eq. 5 (its
  // distance to the line). One that lies behind it at (-3, 4, 0): Eq. 5 says 4 (the line passes
  // under it), the half-line 5 (its origin is the closest point).
  const RepresentativeRay far = ray(0, 0, 0, 1, 0, 0, 10);
  const RepresentativeRay front = ray(2, 4, 0, 0, -1, 0, 1);  // approx_hit (2, 3, 0)
  EXPECT_FLOAT_EQ(glossyRayDistance(front, far), glossyDistance(front, far));
  EXPECT_NEAR(glossyRayDistance(front, far), 3.0f, 1e-6f);
  const RepresentativeRay behind = ray(-3, 6, 0, 0, -1, 0, 2);  // approx_hit (-3, 4, 0)
  EXPECT_NEAR(glossyDistance(behind, far), 4.0f, 1e-6f);
  EXPECT_NEAR(glossyRayDistance(behind, far), 5.0f, 1e-6f);
  EXPECT_FLOAT_EQ(glossyRayDistance(far, behind), glossyRayDistance(behind, far));  // symmetric
}

TEST(GlossyDistance, EscapedSamplesCompareByDirection) {
  // Both samples escaped (kMissDepth): the distance grows with the angle between the rays.
  const RepresentativeRay a = ray(0, 0, 0, 0, 0, -1, kMissDepth);
  const RepresentativeRay b = ray(0.01f, 0, 0, 0, 0, -1, kMissDepth);
  const RepresentativeRay c = ray(0, 0, 0, 0.01f, 0, -1, kMissDepth);
  EXPECT_NEAR(glossyDistance(a, b), 0.01f, 1e-4f);
  EXPECT_GT(glossyDistance(a, c), 50.0f);  // ~kMissDepth * 0.01
}

}  // namespace
}  // namespace rtd
