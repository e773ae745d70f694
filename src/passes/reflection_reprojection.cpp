#include "passes/reflection_reprojection.h"

#include <atomic>

#include "core/parallel.h"

namespace rtd {

namespace {

inline bool isBackground(const FrameData& f, size_t i) {
  const float x = f.plane(Buffer::Normal, 0).data[i], y = f.plane(Buffer::Normal, 1).data[i],
              z = f.plane(Buffer::Normal, 2).data[i];
  return x * x + y * y + z * z < 0.25f;
}

// The world-position feature of Eq. 1 for a mirror pixel: the first non-pure-specular hit; a
// mirror that shows the sky (no reflected hit, zero reflected normal) gets the point kMissDepth
// along its mirror direction, so such pixels match by direction (Eq. 4 with a miss depth).
// Only used where the frame has ReflectedPosition.
struct MirrorFeature {
  const float *p[3] = {}, *n[3] = {}, *o[3] = {}, *d[3] = {};
  explicit MirrorFeature(const FrameData& f) {
    if (!f.has(Buffer::ReflectedPosition)) return;
    for (int k = 0; k < 3; ++k) {
      p[k] = f.plane(Buffer::ReflectedPosition, k).ptr();
      n[k] = f.has(Buffer::ReflectedNormal) ? f.plane(Buffer::ReflectedNormal, k).ptr() : nullptr;
    }
    if (f.has(Buffer::MirrorDirection) && f.has(Buffer::Position))
      for (int k = 0; k < 3; ++k) {
        o[k] = f.plane(Buffer::Position, k).ptr();
        d[k] = f.plane(Buffer::MirrorDirection, k).ptr();
      }
  }
  bool sky(size_t i) const { return n[0] && n[0][i] * n[0][i] + n[1][i] * n[1][i] + n[2][i] * n[2][i] < 0.25f; }
  void at(size_t i, float out[3]) const {
    if (sky(i) && d[0]) {
      float dir[3] = {d[0][i], d[1][i], d[2][i]};
      const float len = std::sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
      const float s = len > 0.0f ? kMissDepth / len : 0.0f;
      for (int k = 0; k < 3; ++k) out[k] = o[k][i] + dir[k] * s;
      return;
    }
    for (int k = 0; k < 3; ++k) out[k] = p[k][i];
  }
  // History tap test of a mirror pixel: reflected normals agree (both skies agree).
  bool agree(size_t i, const MirrorFeature& prev, size_t j, float tolerance) const {
    if (!n[0] || !prev.n[0]) return true;
    const bool a = sky(i), b = prev.sky(j);
    if (a || b) return a == b;
    return n[0][i] * prev.n[0][j] + n[1][i] * prev.n[1][j] + n[2][i] * prev.n[2][j] >= tolerance;
  }
};

inline RepresentativeRay representativeRay(const FrameData& f, size_t i) {
  RepresentativeRay r;
  float len2 = 0.0f;
  for (int k = 0; k < 3; ++k) {
    r.o[k] = f.plane(Buffer::Position, k).data[i];
    r.d[k] = f.plane(Buffer::MirrorDirection, k).data[i];
    len2 += r.d[k] * r.d[k];
  }
  const float inv = len2 > 0.0f ? 1.0f / std::sqrt(len2) : 0.0f;
  for (float& v : r.d) v *= inv;
  const float depth = f.plane(Buffer::SecondaryDistance).data[i];
  r.depth = depth > 0.0f ? depth : kMissDepth;  // 0: the sample escaped
  return r;
}

}  // namespace

void classifySurfaces(const FrameData& f, const SurfaceClassThresholds& t, bool specularLobe, PixelVector<uint8_t>& out) {
  const int w = f.width, h = f.height;
  out.resize(size_t(w) * h);
  const float* rough = f.has(Buffer::Roughness) ? f.plane(Buffer::Roughness).ptr() : nullptr;
  const float* metal = f.has(Buffer::Metalness) && !specularLobe ? f.plane(Buffer::Metalness).ptr() : nullptr;
  parallelRows(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      SurfaceClass c = SurfaceClass::Diffuse;
      if (!isBackground(f, i)) {
        if (!rough) {
          c = specularLobe ? SurfaceClass::Glossy : SurfaceClass::Diffuse;
        } else {
          const float r = rough[i];
          if (r >= t.diffuse) c = SurfaceClass::Diffuse;
          else if (r >= t.reflection) c = SurfaceClass::Glossy;
          else if (r < t.pureSpecular && (!metal || metal[i] >= 0.5f)) c = SurfaceClass::Mirror;
          else c = SurfaceClass::GlossyReflection;
        }
      }
      out[i] = uint8_t(c);
    }
  });
}

void surfaceKeys(const FrameData& f, const PixelVector<uint8_t>& cls, PixelVector<uint32_t>& out) {
  const int w = f.width, h = f.height;
  out.resize(size_t(w) * h);
  const float* id = f.has(Buffer::ObjectId) ? f.plane(Buffer::ObjectId).ptr() : nullptr;
  parallelRows(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      out[i] = surfaceKey(id ? id[i] : 0.0f, cls[i]);
    }
  });
}

bool hasMirrorMotionBuffers(const FrameData& f) { return f.has(Buffer::ReflectedPosition); }
bool hasGlossyMotionBuffers(const FrameData& f) {
  return f.has(Buffer::Position) && f.has(Buffer::MirrorDirection) && f.has(Buffer::SecondaryDistance);
}

void ReflectionSearchFeatures::build(const FrameData& f, const PixelVector<uint8_t>& cls) {
  const int w = f.width, h = f.height;
  records_.resize(size_t(w) * h);  // not filled: only the searched classes' records are read
  const bool mirrors = hasMirrorMotionBuffers(f), glossy = hasGlossyMotionBuffers(f);
  if (!mirrors && !glossy) return;
  const MirrorFeature mirror(f);
  parallelRows(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const SurfaceClass c = SurfaceClass(cls[i]);
      if (c == SurfaceClass::Mirror && mirrors) mirror.at(i, records_[i].point);
      else if (c == SurfaceClass::GlossyReflection && glossy) records_[i].ray = representativeRay(f, i);
    }
  });
}

SearchResult searchReflection(const FrameData& cur, const ReflectionSearchFeatures& prev, const PixelVector<uint8_t>& cls,
                              const PixelVector<uint8_t>& prevCls, const Reprojection& primary, int x, int y,
                              const DiamondSearchOptions& search, int bruteForceRadius, bool glossyOnRay) {
  const int w = cur.width, h = cur.height;
  const size_t i = size_t(y) * w + x;
  const SurfaceClass c = SurfaceClass(cls[i]);
  auto run = [&](const auto& dist) {
    return bruteForceRadius > 0 ? bruteForceSearch(x, y, w, h, dist, bruteForceRadius, search.subpixel, search.fit)
                                : diamondSearch(x, y, primary.prevX.data[i], primary.prevY.data[i], w, h, dist, search);
  };
  if (c == SurfaceClass::Mirror) {
    float wp[3];
    MirrorFeature(cur).at(i, wp);
    return run([&](int qx, int qy) {  // Eq. 1 over previous mirror pixels
      const size_t j = size_t(qy) * w + qx;
      if (SurfaceClass(prevCls[j]) != SurfaceClass::Mirror) return kNoMatch;
      return worldDistance(wp, prev[j].point);
    });
  }
  const RepresentativeRay rp = representativeRay(cur, i);
  return run([&](int qx, int qy) {  // Eq. 5 over previous glossy pixels
    const size_t j = size_t(qy) * w + qx;
    if (SurfaceClass(prevCls[j]) != SurfaceClass::GlossyReflection) return kNoMatch;
    const RepresentativeRay& rq = prev[j].ray;
    return glossyOnRay ? glossyRayDistance(rp, rq) : glossyDistance(rp, rq);
  });
}

void specularReprojection(const FrameData& cur, const FrameData* previous, const PixelVector<uint8_t>& cls,
                          const PixelVector<uint8_t>& prevCls, const Reprojection& primary, SpecularMotion mode,
                          const ReflectionMotionOptions& opt, Reprojection& out, ReflectionMotionStats* stats,
                          ReflectionSearchFeatures* features) {
  out = primary;
  if (!previous || mode == SpecularMotion::Primary || previous->width != cur.width || previous->height != cur.height)
    return;
  const FrameData& prev = *previous;
  const int w = cur.width, h = cur.height;
  const bool mirrors = opt.mirrors && hasMirrorMotionBuffers(cur) && hasMirrorMotionBuffers(prev);
  const bool glossy = opt.glossy && hasGlossyMotionBuffers(cur) && hasGlossyMotionBuffers(prev);
  std::atomic<uint64_t> nMirror{0}, nGlossy{0}, nMatched{0}, nTaps{0};
  const MirrorFeature now(cur), before(prev);
  ReflectionSearchFeatures temporary;
  ReflectionSearchFeatures& prevFeatures = features ? *features : temporary;
  if (mode == SpecularMotion::Reflection && (mirrors || glossy)) prevFeatures.build(prev, prevCls);
  parallelRows(h, [&](int y) {
    uint64_t m = 0, g = 0, matched = 0, taps = 0;
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const SurfaceClass c = SurfaceClass(cls[i]);
      if (!isSpecular(c)) continue;
      if (mode == SpecularMotion::None) {
        out.clearHistory(i);  // NoSpecReproj: no history, and TAA keeps the current colour
        continue;
      }
      const bool mirror = c == SurfaceClass::Mirror && mirrors, gloss = c == SurfaceClass::GlossyReflection && glossy;
      if (!mirror && !gloss) continue;  // Glossy (>= the reflection threshold): primary motion
      (mirror ? m : g) += 1;
      const SearchResult r = searchReflection(cur, prevFeatures, cls, prevCls, primary, x, y, opt.search);
      taps += uint64_t(r.taps);
      out.kind[i] = Reprojection::None;
      out.prevX.data[i] = r.found() ? r.matchX : Reprojection::kOffFrame;
      out.prevY.data[i] = r.found() ? r.matchY : Reprojection::kOffFrame;
      if (!r.found()) continue;
      const bool ok = setBilinear(out, i, r.matchX, r.matchY, [&](int tx, int ty) {
        const size_t j = size_t(ty) * w + tx;
        if (SurfaceClass(prevCls[j]) != c) return false;
        return !mirror || now.agree(i, before, j, opt.normalTolerance);
      });
      matched += ok;
    }
    nMirror += m;
    nGlossy += g;
    nMatched += matched;
    nTaps += taps;
  });
  if (stats) *stats = {nMirror.load(), nGlossy.load(), nMatched.load(), nTaps.load()};
}

}  // namespace rtd
