// Shared pass: reflection motion vectors by diamond search (Voorhuis 2018, Sec. 4.1 and
// Algorithm 1, after Zhu & Ma 2000 and Cheng et al. 2011), the subpixel refinement of Eqs. 2-3,
// the two distance functions (Eq. 1 for pure speculars, Eqs. 4-5 for glossy ones) and the
// brute-force search the paper measures it against (Sec. 7.4). The GLSL twin is
// src/backend/vulkan/shaders/diamond_search.glsl; both evaluate the same taps in the same order.
//
// Pixels are addressed by integer coordinates (x, y), rows from the top; a pixel's centre is
// at (x + 0.5, y + 0.5). A distance function `dist(qx, qy)` scores previous-frame pixel q
// (inside the image) against the current pixel and returns +inf where q cannot match (not a
// specular pixel of the same kind in the previous frame).
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>

namespace rtd {

constexpr float kNoMatch = std::numeric_limits<float>::infinity();

// ---- Distance functions ----

/// Eq. 1: dist(p, q) = || world_p - world_q || (world position of the first non-pure-specular hit).
inline float worldDistance(const float a[3], const float b[3]) {
  const float dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

/// The representative ray of a glossy pixel (Sec. 4.2.1): origin o = primary hit, d = the
/// perfect mirror direction (unit length), and the secondary depth of the sample taken.
struct RepresentativeRay {
  float o[3], d[3];
  float depth;  ///< distance to the sampled secondary hit; kMissDepth where the sample escaped
};

/// Depth given to a sample that escaped (the renderer's secondaryDistance 0): the renderer's
/// sky depth, so two escaped samples compare by the angle between their mirror directions.
constexpr float kMissDepth = 1e4f;

/// Eq. 4: approx_hit(r) = r.o + r.d * depth.
inline void approxHit(const RepresentativeRay& r, float out[3]) {
  for (int k = 0; k < 3; ++k) out[k] = r.o[k] + r.d[k] * r.depth;
}

namespace detail {
/// Eq. 5's operands: v = approx_hit(r_near) - r_far.o for the ray of the smaller secondary
/// depth (r_near; p on ties); returns r_far.
inline const RepresentativeRay& nearHitFromFar(const RepresentativeRay& p, const RepresentativeRay& q, float v[3]) {
  const RepresentativeRay& nearRay = p.depth <= q.depth ? p : q;
  const RepresentativeRay& farRay = p.depth <= q.depth ? q : p;
  float x[3];
  approxHit(nearRay, x);
  for (int k = 0; k < 3; ++k) v[k] = x[k] - farRay.o[k];
  return farRay;
}
}  // namespace detail

/// Eq. 5: the distance from approx_hit of the ray with the smaller secondary depth (r_near) to
/// the line of the other (r_far): || r_far.d x (approx_hit(r_near) - r_far.o) ||, with r_far.d
/// of unit length. Symmetric in p and q (ties in depth take p as near; the distance is then
/// not symmetric only when the two depths are exactly equal and the rays differ).
inline float glossyDistance(const RepresentativeRay& p, const RepresentativeRay& q) {
  float v[3];
  const float* d = detail::nearHitFromFar(p, q, v).d;
  const float c[3] = {d[1] * v[2] - d[2] * v[1], d[2] * v[0] - d[0] * v[2], d[0] * v[1] - d[1] * v[0]};
  return std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
}

/// Eq. 5 on the half-line of r_far (the text's "distance to the other representative ray"):
/// where approx_hit(r_near) projects behind r_far's origin, the distance to that origin. The
/// brute-force reference uses it (rtd::eval::ReflectionMotionSettings::referenceOnRay): over a
/// 200 x 200 window the whole line also matches points behind the far surface, which no
/// reflection sees; the search keeps Eq. 5 as written (docs/methods/reflections.md).
inline float glossyRayDistance(const RepresentativeRay& p, const RepresentativeRay& q) {
  float v[3];
  const float* d = detail::nearHitFromFar(p, q, v).d;
  if (d[0] * v[0] + d[1] * v[1] + d[2] * v[2] < 0) return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return glossyDistance(p, q);
}

// ---- Search ----

/// How the search's best pixel is refined to a subpixel position.
enum class SubpixelFit {
  /// Eqs. 2-3 (the paper): the best 2x2 block's pixel centres weighted by the product of the
  /// other three distances. Biased towards the block's centre: a match half-way between two
  /// pixels is pulled towards the block's other row by up to ~0.2 px.
  inverseDistance,
  /// The minimum of the quadratic through the squared distances of the 3x3 around the best
  /// pixel (central differences: gradient g and Hessian H, offset -H^-1 g, at most 1 px).
  /// Exact where the previous frame's world positions are locally linear in the pixel
  /// coordinates (then |P(q) - world_p|^2 is a quadratic). Falls back to Eqs. 2-3 where a tap
  /// of the 3x3 cannot match or H is not positive definite.
  quadratic,
};

struct DiamondSearchOptions {
  /// Voorhuis' modification: the LDSP taps scaled by stepSize 4 -> 2 -> 1, halved whenever an
  /// iteration finds no better tap. Off: the plain LDSP (stepSize 1) until no improvement.
  bool scaleLdsp = true;
  /// Cap on LDSP iterations (not in the paper, which has none): bounds the cost of a pixel.
  int maxIterations = 64;
  /// Subpixel refinement after the search.
  bool subpixel = true;
  SubpixelFit fit = SubpixelFit::quadratic;
};

/// The LDSP of Cheng et al. 2011 (5 taps: the centre and four taps 2 px away on the axes;
/// the centre is the current best and is not evaluated again) and the SDSP (the centre and its
/// four 4-neighbours), as offsets.
constexpr int kLdspRadius = 2;
constexpr int kDiamond[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};

struct SearchResult {
  int bestX = -1, bestY = -1;     ///< best previous-frame pixel; -1 if no tap matched
  float bestDistance = kNoMatch;
  float matchX = 0, matchY = 0;   ///< matched continuous position (pixel-centre units) after Eqs. 2-3
  int taps = 0;                   ///< distance evaluations (search and refinement)
  bool found() const { return bestX >= 0; }
};

namespace detail {
template <class Dist> struct Scorer {
  const Dist& dist;
  int w, h;
  int taps = 0;
  float operator()(int x, int y) {
    if (x < 0 || y < 0 || x >= w || y >= h) return kNoMatch;
    ++taps;
    return dist(x, y);
  }
};
}  // namespace detail

/// SubpixelFit::quadratic on the 3x3 distances d around the best pixel: true with
/// r.matchX/Y set, false where it does not apply. A tap at distance 0 is the match itself (the
/// first in row order). In units of the 3x3's largest squared distance, so that no product of
/// small distances underflows.
inline bool quadraticMinimum(const float (&d)[3][3], SearchResult& r) {
  float f[3][3], largest = 0.0f;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      if (!(d[j][i] < kNoMatch)) return false;
      f[j][i] = d[j][i] * d[j][i];
      largest = std::max(largest, f[j][i]);  // no NaN here: std::max is fmax, inline
    }
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i)
      if (d[j][i] == 0.0f) {
        r.matchX = float(r.bestX + i - 1) + 0.5f;
        r.matchY = float(r.bestY + j - 1) + 0.5f;
        return true;
      }
  if (!(largest > 0.0f) || !std::isfinite(largest)) return false;
  for (auto& row : f)
    for (float& v : row) v /= largest;
  const float gx = 0.5f * (f[1][2] - f[1][0]), gy = 0.5f * (f[2][1] - f[0][1]);
  const float hxx = f[1][2] - 2.0f * f[1][1] + f[1][0], hyy = f[2][1] - 2.0f * f[1][1] + f[0][1];
  const float hxy = 0.25f * (f[2][2] - f[2][0] - f[0][2] + f[0][0]);
  const float det = hxx * hyy - hxy * hxy;
  if (!(hxx > 0.0f && det > 1e-12f)) return false;
  // Offset of the minimum: -H^-1 g, at most one pixel from the best pixel on each axis.
  const float ux = std::clamp(-(hyy * gx - hxy * gy) / det, -1.0f, 1.0f);  // finite: f <= 1, det > 0
  const float uy = std::clamp(-(hxx * gy - hxy * gx) / det, -1.0f, 1.0f);
  r.matchX = float(r.bestX) + 0.5f + ux;
  r.matchY = float(r.bestY) + 0.5f + uy;
  return true;
}

/// Eqs. 2-3: around the best match b, the 2x2 block W (of the four containing b) with the
/// smallest sum of distances; each pixel q of W weighs w_q = prod_{r in W, r != q} dist(r),
/// and the match is sum w_q coord_q / sum w_q (pixel centres). Blocks with a tap that cannot
/// match are skipped (none left: the centre of b). When two or more distances are 0 the
/// weights vanish and the match is the mean of the zero-distance pixels. Distances are
/// divided by the block's largest before the products, so small distances do not underflow.
template <class Score> void subpixelRefine(Score& score, SearchResult& r, SubpixelFit fit) {
  r.matchX = r.bestX + 0.5f;
  r.matchY = r.bestY + 0.5f;
  float d[3][3];
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i)
      d[j][i] = (i == 1 && j == 1) ? r.bestDistance : score(r.bestX + i - 1, r.bestY + j - 1);
  if (fit == SubpixelFit::quadratic && quadraticMinimum(d, r)) return;
  int bx = -1, by = -1;
  float bestSum = kNoMatch;
  for (int sy = 0; sy < 2; ++sy)
    for (int sx = 0; sx < 2; ++sx) {
      const float s = d[sy][sx] + d[sy][sx + 1] + d[sy + 1][sx] + d[sy + 1][sx + 1];
      if (s < bestSum) {
        bestSum = s;
        bx = sx;
        by = sy;
      }
    }
  if (bx < 0) return;
  float dw[4], cx[4], cy[4], largest = 0.0f;
  int zeros = 0;
  for (int k = 0; k < 4; ++k) {
    const int i = bx + (k & 1), j = by + (k >> 1);
    dw[k] = d[j][i];
    cx[k] = float(r.bestX + i - 1) + 0.5f;
    cy[k] = float(r.bestY + j - 1) + 0.5f;
    largest = std::max(largest, dw[k]);  // the block's distances are finite
    zeros += dw[k] == 0.0f;
  }
  float sw = 0.0f, sx = 0.0f, sy = 0.0f;
  for (int k = 0; k < 4; ++k) {
    float wk;
    if (zeros >= 2) {
      wk = dw[k] == 0.0f ? 1.0f : 0.0f;
    } else {
      wk = 1.0f;  // Eq. 2: the product of the other three (normalized) distances
      for (int m = 0; m < 4; ++m)
        if (m != k) wk *= dw[m] / largest;
    }
    sw += wk;
    sx += wk * cx[k];
    sy += wk * cy[k];
  }
  if (sw > 0.0f) {
    r.matchX = sx / sw;  // Eq. 3
    r.matchY = sy / sw;
  }
}

/// Algorithm 1 for current pixel (px, py) in a w x h previous frame: starts at (px, py) and at
/// the pixel containing `startX, startY` (the primary-hit reprojection of the pixel centre,
/// i.e. coords(p) - primaryMV), keeps the better; then LDSP iterations (see
/// DiamondSearchOptions), one final SDSP step, and Eqs. 2-3. Taps outside the image do not
/// match. The motion vector (ours: previous minus current) is match - (px + 0.5, py + 0.5).
template <class Dist>
SearchResult diamondSearch(int px, int py, float startX, float startY, int w, int h, const Dist& dist,
                           const DiamondSearchOptions& opt = {}) {
  detail::Scorer<Dist> score{dist, w, h};
  SearchResult r;
  int bestX = px, bestY = py;
  float bestDist = score(px, py);
  if (std::isfinite(startX) && std::isfinite(startY) && std::fabs(startX) < 1e6f && std::fabs(startY) < 1e6f) {
    const int mx = int(std::floor(startX)), my = int(std::floor(startY));
    if (mx != px || my != py) {
      const float dm = score(mx, my);
      if (dm < bestDist) {
        bestDist = dm;
        bestX = mx;
        bestY = my;
      }
    }
  }
  int step = opt.scaleLdsp ? 4 : 1;
  int centerX = bestX, centerY = bestY;
  for (int it = 0; it < opt.maxIterations; ++it) {
    const int reach = kLdspRadius * step;
    for (const auto& o : kDiamond) {
      const int qx = centerX + o[0] * reach, qy = centerY + o[1] * reach;
      const float dq = score(qx, qy);
      if (dq < bestDist) {
        bestDist = dq;
        bestX = qx;
        bestY = qy;
      }
    }
    if (bestX == centerX && bestY == centerY) {
      if (step == 1) break;
      step /= 2;
    }
    centerX = bestX;
    centerY = bestY;
  }
  for (const auto& o : kDiamond) {  // SDSP
    const int qx = centerX + o[0], qy = centerY + o[1];
    const float dq = score(qx, qy);
    if (dq < bestDist) {
      bestDist = dq;
      bestX = qx;
      bestY = qy;
    }
  }
  if (bestDist < kNoMatch) {
    r.bestX = bestX;
    r.bestY = bestY;
    r.bestDistance = bestDist;
    if (opt.subpixel) {
      subpixelRefine(score, r, opt.fit);
    } else {
      r.matchX = bestX + 0.5f;
      r.matchY = bestY + 0.5f;
    }
  }
  r.taps = score.taps;
  return r;
}

/// The reference of Sec. 7.4: the best tap in the (2 radius) x (2 radius) window around p
/// (radius 100: the paper's 200 x 200), ties to the first in row order, then the same
/// subpixel refinement.
template <class Dist>
SearchResult bruteForceSearch(int px, int py, int w, int h, const Dist& dist, int radius = 100, bool subpixel = true,
                              SubpixelFit fit = SubpixelFit::quadratic) {
  detail::Scorer<Dist> score{dist, w, h};
  SearchResult r;
  for (int qy = std::max(0, py - radius); qy < std::min(h, py + radius); ++qy)
    for (int qx = std::max(0, px - radius); qx < std::min(w, px + radius); ++qx) {
      const float dq = score(qx, qy);
      if (dq < r.bestDistance) {
        r.bestDistance = dq;
        r.bestX = qx;
        r.bestY = qy;
      }
    }
  if (r.found()) {
    if (subpixel) {
      subpixelRefine(score, r, fit);
    } else {
      r.matchX = r.bestX + 0.5f;
      r.matchY = r.bestY + 0.5f;
    }
  }
  r.taps = score.taps;
  return r;
}

}  // namespace rtd
