#include "synthetic/synthetic.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace rtd::synthetic {

namespace {

struct V3 {
  float x, y, z;
};
inline V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline V3 operator*(V3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
inline float dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline V3 normalize(V3 a) { return a * (1.0f / std::sqrt(dot(a, a))); }

// PCG-style hash to a uniform in (0, 1).
inline float uniform(uint32_t a, uint32_t b, uint32_t c) {
  uint32_t h = a * 747796405u + b * 2891336453u + c * 277803737u + 0x9e3779b9u;
  h = ((h >> ((h >> 28u) + 4u)) ^ h) * 277803737u;
  h = (h >> 22u) ^ h;
  return (float(h >> 8) + 0.5f) * (1.0f / 16777216.0f);
}

struct Hit {
  float t = INFINITY;
  V3 n{0, 0, 0};
  int id = 0;
};

constexpr V3 kSphereCentre{0.0f, 0.75f, 0.0f};
constexpr float kSphereRadius = 0.75f;
constexpr float kWallZ = -4.0f;

Hit intersect(V3 o, V3 d) {
  Hit h;
  if (d.y < 0) {  // floor y = 0
    float t = -o.y / d.y;
    if (t > 0 && t < h.t) h = {t, {0, 1, 0}, 1};
  }
  if (d.z < 0) {  // wall z = kWallZ
    float t = (kWallZ - o.z) / d.z;
    if (t > 0 && t < h.t) h = {t, {0, 0, 1}, 2};
  }
  V3 oc = o - kSphereCentre;
  float b = dot(oc, d), c = dot(oc, oc) - kSphereRadius * kSphereRadius, disc = b * b - c;
  if (disc > 0) {
    float t = -b - std::sqrt(disc);
    if (t > 0 && t < h.t) h = {t, normalize(o + d * t - kSphereCentre), 3};
  }
  return h;
}

V3 albedoAt(const Hit& h, V3 p) {
  if (h.id == 1) {
    const bool odd = (int(std::floor(p.x * 2.0f)) + int(std::floor(p.z * 2.0f))) & 1;
    return odd ? V3{0.8f, 0.8f, 0.75f} : V3{0.25f, 0.3f, 0.35f};
  }
  if (h.id == 2) return {0.6f, 0.55f, 0.5f};
  if (h.id == 3) return {0.9f, 0.4f, 0.3f};
  return {0, 0, 0};
}

V3 cameraPosition(const Scene& s, int index) { return {s.cameraSpeed * float(index), 1.0f, 5.0f}; }

// Camera-to-world rotation of frame `index`: a yaw about +y, applied to a camera-space vector.
struct Yaw {
  float c = 1, s = 0;
  Yaw(const Scene& scene, int index) {
    if (scene.cameraYawSpeed != 0) c = std::cos(scene.cameraYawSpeed * index), s = std::sin(scene.cameraYawSpeed * index);
  }
  V3 toWorld(V3 v) const { return s == 0 ? v : V3{c * v.x + s * v.z, v.y, -s * v.x + c * v.z}; }
  V3 toCamera(V3 v) const { return s == 0 ? v : V3{c * v.x - s * v.z, v.y, s * v.x + c * v.z}; }
};

// The radical inverse of i in base b (Halton sequence), in [0, 1).
float radicalInverse(int i, int b) {
  float f = 1, r = 0;
  for (; i > 0; i /= b) {
    f /= float(b);
    r += f * float(i % b);
  }
  return r;
}

Camera cameraOf(const Scene& s, int index) {
  Camera c;
  V3 e = cameraPosition(s, index);
  const Yaw yaw(s, index);
  // worldToCamera = [R^T | -R^T e] for the camera-to-world rotation R.
  const V3 ex = yaw.toCamera({1, 0, 0}), ey = yaw.toCamera({0, 1, 0}), ez = yaw.toCamera({0, 0, 1}), t = yaw.toCamera(e);
  c.worldToCamera = {ex.x, ey.x, ez.x, -t.x, ex.y, ey.y, ez.y, -t.y, ex.z, ey.z, ez.z, -t.z, 0, 0, 0, 1};
  const float f = 1.0f / std::tan(s.verticalFov * 0.5f), aspect = float(s.width) / float(s.height);
  const float n = 0.1f, fa = 100.0f;
  c.projection = {f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, -(fa + n) / (fa - n), -2 * fa * n / (fa - n), 0, 0, -1, 0};
  c.valid = true;
  return c;
}

V3 rayDirection(const Scene& s, float px, float py) {
  const float tanHalf = std::tan(s.verticalFov * 0.5f), aspect = float(s.width) / float(s.height);
  const float sx = (2.0f * px / s.width - 1.0f) * tanHalf * aspect;
  const float sy = (1.0f - 2.0f * py / s.height) * tanHalf;
  return normalize({sx, sy, -1.0f});
}

const V3 kLight = normalize({0.4f, 1.0f, 0.6f});

// Noise-free radiance leaving the surface point p (hit `hit`) in frame `index`: the sun with
// the sphere's shadow plus an ambient term, view-independent.
V3 radianceAt(const Scene& s, int index, const Hit& hit, V3 p) {
  if (!hit.id) return {0.1f, 0.12f, 0.15f};  // sky
  const V3 a = albedoAt(hit, p);
  const bool sunOn = s.sunOffFrame < 0 || index < s.sunOffFrame;
  float sun = sunOn ? std::max(0.0f, dot(hit.n, kLight)) : 0.0f;
  if (sun > 0 && intersect(p + hit.n * 1e-3f, kLight).id == 3) sun = 0;
  return a * (0.25f + 1.5f * sun);
}

// The exponential variate of pixel (x, y) in frame `index`: the synthetic sample's "seed".
float noiseAt(const Scene& s, int x, int y, int index) {
  return s.noise > 0 ? 1.0f + s.noise * (-std::log(uniform(uint32_t(x), uint32_t(y), s.seed * 7919u + uint32_t(index))) - 1.0f)
                     : 1.0f;
}

float luminance(V3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

// Gradient samples of frame `index` >= 1 (docs/sequence-format.md): the brightest sample of each
// stratum of frame index - 1, its surface point projected with this frame's camera (the scene
// is static), kept where it is still visible and lands on the same object, re-shaded with its
// noise variate; the brightest wins a stratum two land in.
void writeGradientSamples(const Scene& s, int index, Frame& f) {
  const int w = s.width, h = s.height, sw = (w + 2) / 3, sh = (h + 2) / 3;
  const V3 eye = cameraPosition(s, index), prevEye = cameraPosition(s, index - 1);
  const float tanHalf = std::tan(s.verticalFov * 0.5f), aspect = float(w) / float(h);
  std::vector<float> best(size_t(sw) * sh, -1.0f);
  for (int gy = 0; gy < sh; ++gy)
    for (int gx = 0; gx < sw; ++gx) {
      float lum = -1.0f;
      int bx = 0, by = 0;
      Hit bh;
      V3 bp{0, 0, 0};
      for (int y = 3 * gy; y < std::min(h, 3 * gy + 3); ++y)
        for (int x = 3 * gx; x < std::min(w, 3 * gx + 3); ++x) {
          const V3 d = rayDirection(s, x + 0.5f, y + 0.5f);
          const Hit hit = intersect(prevEye, d);
          if (!hit.id) continue;
          const V3 p = prevEye + d * hit.t;
          const float l = luminance(radianceAt(s, index - 1, hit, p) * noiseAt(s, x, y, index - 1));
          if (l > lum) lum = l, bx = x, by = y, bh = hit, bp = p;
        }
      if (lum < 0) continue;
      const V3 q = bp - eye;
      if (q.z >= 0) continue;
      const float px = (q.x / -q.z / (tanHalf * aspect) * 0.5f + 0.5f) * w;
      const float py = (0.5f - q.y / -q.z / tanHalf * 0.5f) * h;
      if (!(px >= 0 && py >= 0 && px < w && py < h)) continue;
      const int lx = std::min(w - 1, int(px)), ly = std::min(h - 1, int(py));
      const float t = std::sqrt(dot(q, q));
      if (intersect(eye, q * (1.0f / t)).t < t * (1.0f - 1e-3f)) continue;  // hidden now
      if (f[Buffer::ObjectId].at(lx, ly) != float(bh.id)) continue;
      const size_t k = size_t(ly / 3) * sw + lx / 3;
      if (lum <= best[k]) continue;
      if (best[k] >= 0)  // a dimmer sample landed here first
        for (int y = ly / 3 * 3; y < std::min(h, ly / 3 * 3 + 3); ++y)
          for (int x = lx / 3 * 3; x < std::min(w, lx / 3 * 3 + 3); ++x) f[Buffer::GradientSample].at(x, y) = 0;
      best[k] = lum;
      f[Buffer::GradientSample].at(lx, ly) = 1;
      f[Buffer::GradientPrevious].at(lx, ly) = lum;
      f[Buffer::GradientCurrent].at(lx, ly) = luminance(radianceAt(s, index, bh, bp) * noiseAt(s, bx, by, index - 1));
    }
}

}  // namespace

std::array<float, 2> jitterOf(const Scene& s, int index) {
  if (!s.jitter) return {0, 0};
  return {radicalInverse(index + 1, 2) - 0.5f, radicalInverse(index + 1, 3) - 0.5f};
}

Frame makeFrame(const Scene& s, int index, Image* reference) {
  const int w = s.width, h = s.height;
  Frame f;
  f.number = index + 1;
  f.width = w;
  f.height = h;
  f.camera = cameraOf(s, index);
  for (Buffer b : {Buffer::Color, Buffer::Albedo, Buffer::Normal, Buffer::Depth, Buffer::Position, Buffer::Motion,
                   Buffer::ObjectId, Buffer::Roughness})
    f[b] = Image(w, h, bufferChannelCount(b));
  if (reference) *reference = Image(w, h, 3);

  const V3 eye = cameraPosition(s, index), prevEye = cameraPosition(s, index - 1);
  const Yaw yaw(s, index), prevYaw(s, index - 1);
  const auto jitter = jitterOf(s, index);
  const float tanHalf = std::tan(s.verticalFov * 0.5f), aspect = float(w) / float(h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      // The sample position (pixel centre plus jitter), in pixels.
      const float fx = x + 0.5f + jitter[0], fy = y + 0.5f + jitter[1];
      const V3 dc = rayDirection(s, fx, fy), d = yaw.toWorld(dc);
      const Hit hit = intersect(eye, d);
      const V3 p = eye + d * hit.t;
      const V3 radiance = radianceAt(s, index, hit, p);
      if (hit.id) {
        const V3 a = albedoAt(hit, p);
        f[Buffer::Albedo].at(x, y, 0) = a.x;
        f[Buffer::Albedo].at(x, y, 1) = a.y;
        f[Buffer::Albedo].at(x, y, 2) = a.z;
        f[Buffer::Normal].at(x, y, 0) = hit.n.x;
        f[Buffer::Normal].at(x, y, 1) = hit.n.y;
        f[Buffer::Normal].at(x, y, 2) = hit.n.z;
        f[Buffer::Depth].at(x, y) = hit.t * -dc.z;  // view depth along -z
        f[Buffer::Position].at(x, y, 0) = p.x;
        f[Buffer::Position].at(x, y, 1) = p.y;
        f[Buffer::Position].at(x, y, 2) = p.z;
        f[Buffer::ObjectId].at(x, y) = float(hit.id);
        f[Buffer::Roughness].at(x, y) = 1.0f;
        // Motion: where p was on screen with the previous (unjittered) camera, static scene,
        // from where it is now (the sample position).
        const V3 q = prevYaw.toCamera(p - prevEye);
        const float px = (q.x / -q.z / (tanHalf * aspect) * 0.5f + 0.5f) * w;
        const float py = (0.5f - q.y / -q.z / tanHalf * 0.5f) * h;
        f[Buffer::Motion].at(x, y, 0) = px - fx;
        f[Buffer::Motion].at(x, y, 1) = py - fy;
      } else {
        f[Buffer::Depth].at(x, y) = 1e4f;
      }
      const float noise = noiseAt(s, x, y, index);
      f[Buffer::Color].at(x, y, 0) = radiance.x * noise;
      f[Buffer::Color].at(x, y, 1) = radiance.y * noise;
      f[Buffer::Color].at(x, y, 2) = radiance.z * noise;
      if (reference) {
        reference->at(x, y, 0) = radiance.x;
        reference->at(x, y, 1) = radiance.y;
        reference->at(x, y, 2) = radiance.z;
      }
    }
  if (s.gradientSamples) {
    // Every frame has the buffers (a sequence's frames all hold the same ones); frame 0 has no
    // previous frame, hence no samples.
    for (Buffer b : {Buffer::GradientSample, Buffer::GradientPrevious, Buffer::GradientCurrent}) f[b] = Image(w, h, 1);
    if (index > 0) writeGradientSamples(s, index, f);
  }
  return f;
}

}  // namespace rtd::synthetic
