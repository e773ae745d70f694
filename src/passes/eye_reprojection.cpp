#include "passes/eye_reprojection.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "core/parallel.h"

namespace rtd {

bool ViewProjection::project(const float p[3], float& px, float& py, float& depth) const {
  const auto& m = worldToCamera;
  float v[4];
  for (int r = 0; r < 4; ++r) v[r] = m[r * 4 + 0] * p[0] + m[r * 4 + 1] * p[1] + m[r * 4 + 2] * p[2] + m[r * 4 + 3];
  float c[4];
  for (int r = 0; r < 4; ++r)
    c[r] = projection[r * 4 + 0] * v[0] + projection[r * 4 + 1] * v[1] + projection[r * 4 + 2] * v[2] +
           projection[r * 4 + 3] * v[3];
  if (!(c[3] > 0.0f)) return false;
  px = (c[0] / c[3] * 0.5f + 0.5f) * float(width);
  py = (0.5f - c[1] / c[3] * 0.5f) * float(height);  // NDC y is up, rows go down
  depth = -v[2];  // the camera looks down -Z
  return std::abs(px) < 1e6f && std::abs(py) < 1e6f;
}

EyeGuide EyeGuide::of(const FrameData& f) {
  EyeGuide g;
  g.position = &f.planes(Buffer::Position);
  g.normal = &f.planes(Buffer::Normal);
  g.depth = &f.plane(Buffer::Depth);
  if (f.has(Buffer::ObjectId)) g.objectId = &f.plane(Buffer::ObjectId);
  if (f.has(Buffer::DepthGradient)) g.depthGradient = &f.planes(Buffer::DepthGradient);
  g.view = ViewProjection::of(f.camera, f.width, f.height);
  return g;
}

EyeTaps eyeTaps(const EyeGuide& t, const EyeGuide& src, const ReprojectionSettings& s, size_t i) {
  EyeTaps out;
  const float n[3] = {(*t.normal)[0].data[i], (*t.normal)[1].data[i], (*t.normal)[2].data[i]};
  if (n[0] * n[0] + n[1] * n[1] + n[2] * n[2] < 0.25f) return out;  // no surface: nothing to share
  const float p[3] = {(*t.position)[0].data[i], (*t.position)[1].data[i], (*t.position)[2].data[i]};
  float px, py, z;
  if (!src.view.project(p, px, py, z)) return out;
  const int w = src.view.width, h = src.view.height;
  // Bilinear footprint: taps are pixel centres, so the top-left tap is floor(p - 0.5).
  const float fx = px - 0.5f, fy = py - 0.5f;
  const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
  const float ax = fx - float(x0), ay = fy - float(y0);
  const float bw[4] = {(1 - ax) * (1 - ay), ax * (1 - ay), (1 - ax) * ay, ax * ay};
  const float id = t.objectId ? t.objectId->data[i] : 0.0f;
  float sum = 0.0f;
  for (int k = 0; k < 4; ++k) {
    const int x = x0 + (k & 1), y = y0 + (k >> 1);
    if (bw[k] <= 0.0f || x < 0 || y < 0 || x >= w || y >= h) continue;
    const size_t j = size_t(y) * w + x;
    if (src.valid && !(src.valid->data[j] > 0.0f)) continue;
    const float q[3] = {(*src.normal)[0].data[j], (*src.normal)[1].data[j], (*src.normal)[2].data[j]};
    if (!(n[0] * q[0] + n[1] * q[1] + n[2] * q[2] >= s.normalTolerance)) continue;  // also rejects no-surface taps
    if (s.testObjectId && t.objectId && src.objectId && src.objectId->data[j] != id) continue;
    if (s.testDepth) {
      // The point's own depth in the source view against what the source sees there: a
      // point hidden behind something else in the source view fails.
      float slope = 0.0f;
      if (src.depthGradient)
        slope = std::max(std::abs((*src.depthGradient)[0].data[j]), std::abs((*src.depthGradient)[1].data[j]));
      if (!(std::abs(src.depth->data[j] - z) <= s.depthTolerance * z + s.depthGradientScale * slope)) continue;
    }
    out.index[out.count] = int32_t(j);
    out.weight[out.count++] = bw[k];
    sum += bw[k];
  }
  if (!(sum > 1e-4f)) {
    out.count = 0;
    return out;
  }
  for (int k = 0; k < out.count; ++k) out.weight[k] /= sum;
  return out;
}

size_t eyeReproject(const EyeGuide& target, const EyeGuide& source, const ReprojectionSettings& s, float blend,
                    const Plane3& targetLight, const Plane3& sourceLight, Plane3& out, Plane* reprojected) {
  const int w = target.view.width;
  std::atomic<size_t> total{0};
  parallelRows(target.view.height, [&](int y) {
    size_t count = 0;
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const EyeTaps taps = eyeTaps(target, source, s, i);
      if (reprojected) reprojected->data[i] = taps.count ? 1.0f : 0.0f;
      for (int c = 0; c < 3; ++c) {
        const float a = targetLight[c].data[i];
        if (!taps.count) {
          out[c].data[i] = a;
          continue;
        }
        float b = 0.0f;
        for (int k = 0; k < taps.count; ++k) b += taps.weight[k] * sourceLight[c].data[taps.index[k]];
        out[c].data[i] = (1.0f - blend) * a + blend * b;
      }
      count += taps.count > 0;
    }
    total += count;
  });
  return total.load();
}

}  // namespace rtd
