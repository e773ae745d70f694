#include "core/conventions.h"

#include "core/flush.h"
#include "core/parallel.h"
#include "core/settings_reflect.h"
#include "rtd/error.h"

namespace rtd {

namespace {
constexpr const char* kWhat = "frame conventions";  // how errors name them
}  // namespace

bool FrameConventions::native() const {
  const FrameConventions d;
  return motionUnits == d.motionUnits && motionYUp == d.motionYUp && motionToCurrent == d.motionToCurrent &&
         motionIncludesJitter == d.motionIncludesJitter && jitterX == 0 && jitterY == 0 &&
         normalSpace == d.normalSpace && depth == d.depth;
}

std::vector<SettingInfo> conventionSettings(const FrameConventions& c) { return detail::listSettings(c); }

void setConvention(FrameConventions& c, std::string_view name, std::string_view value) {
  FrameConventions copy = c;
  detail::SettingSetter setter{name, value};
  copy.visit(setter);
  if (!setter.found) throw Error("frame conventions have no field '" + std::string(name) + "'");
  detail::validateSettings(copy, kWhat);
  c = copy;
}

ConventionTransform conventionTransform(const FrameConventions& c, const Camera& camera, int w, int h,
                                        bool hasNormals) {
  // Typed conventions get the checks of those set by name (ranges, enum values).
  detail::validateSettings(c, kWhat);
  for (float v : c.depthProjection)
    if (!std::isfinite(v)) throw Error("frame conventions: depthProjection has a non-finite entry");
  ConventionTransform t;
  using C = FrameConventions;

  // Motion: to pixels, y down, pointing to the previous position; then the jitter difference.
  float sx = 1, sy = 1;
  if (c.motionUnits == C::MotionUnits::Uv) sx = float(w), sy = float(h);
  if (c.motionUnits == C::MotionUnits::Ndc) sx = 0.5f * float(w), sy = 0.5f * float(h);
  if (c.motionYUp) sy = -sy;
  if (c.motionToCurrent) sx = -sx, sy = -sy;
  t.motionScale[0] = sx;
  t.motionScale[1] = sy;
  if (c.motionIncludesJitter) {
    // A jittered projection shows the point at unjittered position q at q - jitter, so jittered
    // motion is the true motion - previousJitter + jitter.
    t.motionOffset[0] = c.previousJitterX - c.jitterX;
    t.motionOffset[1] = c.previousJitterY - c.jitterY;
  }
  t.motion = sx != 1 || sy != 1 || t.motionOffset[0] != 0 || t.motionOffset[1] != 0;

  if (c.normalSpace == C::NormalSpace::View && hasNormals) {
    if (!camera.valid)
      throw Error("frame conventions: view-space normals need the frame's camera (Camera::valid with worldToCamera)");
    // Normals transform with the inverse transpose of the view-to-world map, i.e. with the
    // transpose of worldToCamera's upper 3x3 (any invertible one, rotation or not).
    const auto& m = camera.worldToCamera;
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) t.normalMatrix[r * 3 + k] = m[k * 4 + r];
    t.normals = true;
  }

  if (c.depth == C::DepthKind::Hardware) {
    const auto& p = c.depthProjection;
    t.depth = true;
    if (c.depthRange == C::DepthRange::MinusOneToOne) t.ndcScale = 2, t.ndcOffset = -1;
    t.p22 = p[10], t.p23 = p[11], t.p32 = p[14], t.p33 = p[15];
  }

  t.jitter = c.jitterX != 0 || c.jitterY != 0;
  t.jitterPixels[0] = c.jitterX;
  t.jitterPixels[1] = c.jitterY;
  return t;
}

void applyConventions(const ConventionTransform& t, FrameData& f) {
  const int w = f.width;
  if (t.motion && f.has(Buffer::Motion)) {
    parallelRows(f.height, [&](int y) {
      for (int c = 0; c < 2; ++c) {
        float* m = f.plane(Buffer::Motion, c).row(y);
        for (int x = 0; x < w; ++x) m[x] = flushTiny(m[x] * t.motionScale[c] + t.motionOffset[c]);
      }
    });
  }
  if (t.normals && f.has(Buffer::Normal)) {
    const float* a = t.normalMatrix;
    parallelRows(f.height, [&](int y) {
      float* n[3] = {f.plane(Buffer::Normal, 0).row(y), f.plane(Buffer::Normal, 1).row(y), f.plane(Buffer::Normal, 2).row(y)};
      for (int x = 0; x < w; ++x) {
        const float vx = n[0][x], vy = n[1][x], vz = n[2][x];
        const float wx = a[0] * vx + a[1] * vy + a[2] * vz, wy = a[3] * vx + a[4] * vy + a[5] * vz,
                    wz = a[6] * vx + a[7] * vy + a[8] * vz;
        const float len2 = wx * wx + wy * wy + wz * wz;
        const float s = len2 > 0 ? 1.0f / std::sqrt(len2) : 0.0f;  // background (zero) normals stay zero
        n[0][x] = flushTiny(wx * s), n[1][x] = flushTiny(wy * s), n[2][x] = flushTiny(wz * s);
      }
    });
  }
  if (t.depth && f.has(Buffer::Depth)) {
    parallelRows(f.height, [&](int y) {
      float* z = f.plane(Buffer::Depth).row(y);
      for (int x = 0; x < w; ++x) z[x] = flushTiny(t.linearDepth(z[x]));
    });
  }
}

Camera jitterCompensated(const Camera& previous, const ConventionTransform& t, int w, int h) {
  if (!t.jitter) return previous;
  // Reprojection maps clip (x, y, w) to pixels as ((x/w + 1) / 2 * width, (1 - y/w) / 2 * height):
  // adding k * w to x moves the result by k * width / 2 pixels, adding m * w to y by -m * height / 2.
  Camera c = previous;
  const float kx = -2.0f * t.jitterPixels[0] / float(w), ky = 2.0f * t.jitterPixels[1] / float(h);
  for (int k = 0; k < 4; ++k) {
    c.projection[k] += kx * previous.projection[12 + k];
    c.projection[4 + k] += ky * previous.projection[12 + k];
  }
  return c;
}

std::array<float, 9> worldToViewRotation(const Camera& camera) {
  std::array<float, 9> r{1, 0, 0, 0, 1, 0, 0, 0, 1};
  if (camera.valid)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r[size_t(i) * 3 + j] = camera.worldToCamera[size_t(i) * 4 + j];
  return r;
}

}  // namespace rtd
