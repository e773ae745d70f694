// Reflection motion vectors by diamond search (Voorhuis 2018, Algorithm 1) with the subpixel
// refinement of Eqs. 2-3 or the quadratic fit (SubpixelFit) and the distance functions of Eqs. 1, 4, 5: the GLSL twin of
// src/passes/diamond_search.h, tap for tap in the same order. Included once for the constants
// and distance functions; included again with DS_SEARCH defined for the search, after the
// shader has defined `float searchDistance(int qx, int qy)` (a previous-frame pixel inside the
// image; kNoMatch where it cannot match) and DS_WIDTH / DS_HEIGHT.
#ifndef RTD_DIAMOND_SEARCH_DISTANCES
#define RTD_DIAMOND_SEARCH_DISTANCES

const float kNoMatch = 1.0 / 0.0;  // +inf
const float kMissDepth = 1e4;

// Eq. 1.
float worldDistance(vec3 a, vec3 b) {
  precise vec3 d = a - b;
  precise float s = d.x * d.x + d.y * d.y + d.z * d.z;
  return sqrt(s);
}

// Eq. 4 and Eq. 5 (d of unit length; the nearer sample by depth is measured to the farther ray).
float glossyDistance(vec3 po, vec3 pd, float pdepth, vec3 qo, vec3 qd, float qdepth) {
  const bool pNear = pdepth <= qdepth;
  const vec3 no = pNear ? po : qo, nd = pNear ? pd : qd;
  const float ndepth = pNear ? pdepth : qdepth;
  const vec3 fo = pNear ? qo : po, fd = pNear ? qd : pd;
  precise vec3 x;
  x.x = no.x + nd.x * ndepth;
  x.y = no.y + nd.y * ndepth;
  x.z = no.z + nd.z * ndepth;
  precise vec3 v = x - fo;
  precise vec3 c;
  c.x = fd.y * v.z - fd.z * v.y;
  c.y = fd.z * v.x - fd.x * v.z;
  c.z = fd.x * v.y - fd.y * v.x;
  precise float s = c.x * c.x + c.y * c.y + c.z * c.z;
  return sqrt(s);
}

#endif

#ifdef DS_SEARCH
struct SearchResult {
  ivec2 best;      // (-1, -1) when nothing matched
  float bestDistance;
  vec2 match;      // continuous position, pixel-centre units
};

float dsScore(int qx, int qy) {
  if (qx < 0 || qy < 0 || qx >= int(DS_WIDTH) || qy >= int(DS_HEIGHT)) return kNoMatch;
  return searchDistance(qx, qy);
}

const ivec2 kDiamond[4] = ivec2[4](ivec2(1, 0), ivec2(-1, 0), ivec2(0, 1), ivec2(0, -1));

// SubpixelFit::quadratic (quadraticMinimum in diamond_search.h): the minimum of the quadratic
// through the 3x3's squared distances, in units of the largest; false where it does not apply.
bool quadraticMinimum(float d[9], inout SearchResult r) {
  float f[9];
  float largest = 0.0;
  for (int k = 0; k < 9; ++k) {
    if (!(d[k] < kNoMatch)) return false;
    f[k] = d[k] * d[k];
    largest = max(largest, f[k]);
  }
  for (int k = 0; k < 9; ++k)
    if (d[k] == 0.0) {  // a tap at distance 0 is the match (the first in row order)
      r.match = vec2(r.best + ivec2(k % 3 - 1, k / 3 - 1)) + 0.5;
      return true;
    }
  if (!(largest > 0.0) || isinf(largest)) return false;
  for (int k = 0; k < 9; ++k) f[k] /= largest;
  precise float gx = 0.5 * (f[5] - f[3]), gy = 0.5 * (f[7] - f[1]);
  precise float hxx = f[5] - 2.0 * f[4] + f[3], hyy = f[7] - 2.0 * f[4] + f[1];
  precise float hxy = 0.25 * (f[8] - f[6] - f[2] + f[0]);
  precise float det = hxx * hyy - hxy * hxy;
  if (!(hxx > 0.0 && det > 1e-12)) return false;
  precise float ux = -(hyy * gx - hxy * gy) / det, uy = -(hxx * gy - hxy * gx) / det;
  r.match = vec2(r.best) + 0.5 + clamp(vec2(ux, uy), -1.0, 1.0);
  return true;
}

void subpixelRefine(inout SearchResult r, bool quadratic) {
  r.match = vec2(r.best) + 0.5;
  float d[9];
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i)
      d[j * 3 + i] = (i == 1 && j == 1) ? r.bestDistance : dsScore(r.best.x + i - 1, r.best.y + j - 1);
  if (quadratic && quadraticMinimum(d, r)) return;
  int bx = -1, by = -1;
  float bestSum = kNoMatch;
  for (int sy = 0; sy < 2; ++sy)
    for (int sx = 0; sx < 2; ++sx) {
      precise float s = d[sy * 3 + sx] + d[sy * 3 + sx + 1] + d[(sy + 1) * 3 + sx] + d[(sy + 1) * 3 + sx + 1];
      if (s < bestSum) {
        bestSum = s;
        bx = sx;
        by = sy;
      }
    }
  if (bx < 0) return;
  float dw[4];
  vec2 cc[4];
  float largest = 0.0;
  int zeros = 0;
  for (int k = 0; k < 4; ++k) {
    const int i = bx + (k & 1), j = by + (k >> 1);
    dw[k] = d[j * 3 + i];
    cc[k] = vec2(float(r.best.x + i - 1) + 0.5, float(r.best.y + j - 1) + 0.5);
    largest = max(largest, dw[k]);
    zeros += dw[k] == 0.0 ? 1 : 0;
  }
  precise float sw = 0.0, sx = 0.0, sy = 0.0;
  for (int k = 0; k < 4; ++k) {
    precise float wk;
    if (zeros >= 2) {
      wk = dw[k] == 0.0 ? 1.0 : 0.0;
    } else {
      wk = 1.0;  // Eq. 2
      for (int m = 0; m < 4; ++m)
        if (m != k) wk *= dw[m] / largest;
    }
    sw += wk;
    sx += wk * cc[k].x;
    sy += wk * cc[k].y;
  }
  if (sw > 0.0) r.match = vec2(sx / sw, sy / sw);  // Eq. 3
}

// Algorithm 1 from pixel p with the second start `start` (p's primary reprojection).
SearchResult diamondSearch(ivec2 p, vec2 start, bool scaleLdsp, int maxIterations, bool subpixel, bool quadratic) {
  SearchResult r;
  r.best = ivec2(-1);
  r.bestDistance = kNoMatch;
  ivec2 best = p;
  float bestDist = dsScore(p.x, p.y);
  if (abs(start.x) < 1e6 && abs(start.y) < 1e6) {  // also false for inf and NaN
    const ivec2 m = ivec2(floor(start));
    if (m != p) {
      const float dm = dsScore(m.x, m.y);
      if (dm < bestDist) {
        bestDist = dm;
        best = m;
      }
    }
  }
  int step = scaleLdsp ? 4 : 1;
  ivec2 center = best;
  for (int it = 0; it < maxIterations; ++it) {
    const int reach = 2 * step;  // kLdspRadius
    for (int k = 0; k < 4; ++k) {
      const ivec2 q = center + kDiamond[k] * reach;
      const float dq = dsScore(q.x, q.y);
      if (dq < bestDist) {
        bestDist = dq;
        best = q;
      }
    }
    if (best == center) {
      if (step == 1) break;
      step /= 2;
    }
    center = best;
  }
  for (int k = 0; k < 4; ++k) {  // SDSP
    const ivec2 q = center + kDiamond[k];
    const float dq = dsScore(q.x, q.y);
    if (dq < bestDist) {
      bestDist = dq;
      best = q;
    }
  }
  if (bestDist < kNoMatch) {
    r.best = best;
    r.bestDistance = bestDist;
    if (subpixel) subpixelRefine(r, quadratic);
    else r.match = vec2(best) + 0.5;
  }
  return r;
}
#endif
