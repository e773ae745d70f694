// Scene model: math helpers, textures, procedural meshes, animation, camera path, and the JSON
// scene/sequence description parser (format in docs/renderer.md).
#include "render/scene.h"

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <map>
#include <set>
#include <sstream>

#include "render/patterns.h"
#include "rtd/error.h"
#include "rtd/render/procedural.h"

namespace rtd::render {

using nlohmann::json;
namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------
// Math

M4 inverse(const M4& a) {
  double m[16], inv[16];
  for (int i = 0; i < 16; ++i) m[i] = a.m[i];
  inv[0] = m[5] * m[10] * m[15] - m[5] * m[11] * m[14] - m[9] * m[6] * m[15] + m[9] * m[7] * m[14] + m[13] * m[6] * m[11] - m[13] * m[7] * m[10];
  inv[4] = -m[4] * m[10] * m[15] + m[4] * m[11] * m[14] + m[8] * m[6] * m[15] - m[8] * m[7] * m[14] - m[12] * m[6] * m[11] + m[12] * m[7] * m[10];
  inv[8] = m[4] * m[9] * m[15] - m[4] * m[11] * m[13] - m[8] * m[5] * m[15] + m[8] * m[7] * m[13] + m[12] * m[5] * m[11] - m[12] * m[7] * m[9];
  inv[12] = -m[4] * m[9] * m[14] + m[4] * m[10] * m[13] + m[8] * m[5] * m[14] - m[8] * m[6] * m[13] - m[12] * m[5] * m[10] + m[12] * m[6] * m[9];
  inv[1] = -m[1] * m[10] * m[15] + m[1] * m[11] * m[14] + m[9] * m[2] * m[15] - m[9] * m[3] * m[14] - m[13] * m[2] * m[11] + m[13] * m[3] * m[10];
  inv[5] = m[0] * m[10] * m[15] - m[0] * m[11] * m[14] - m[8] * m[2] * m[15] + m[8] * m[3] * m[14] + m[12] * m[2] * m[11] - m[12] * m[3] * m[10];
  inv[9] = -m[0] * m[9] * m[15] + m[0] * m[11] * m[13] + m[8] * m[1] * m[15] - m[8] * m[3] * m[13] - m[12] * m[1] * m[11] + m[12] * m[3] * m[9];
  inv[13] = m[0] * m[9] * m[14] - m[0] * m[10] * m[13] - m[8] * m[1] * m[14] + m[8] * m[2] * m[13] + m[12] * m[1] * m[10] - m[12] * m[2] * m[9];
  inv[2] = m[1] * m[6] * m[15] - m[1] * m[7] * m[14] - m[5] * m[2] * m[15] + m[5] * m[3] * m[14] + m[13] * m[2] * m[7] - m[13] * m[3] * m[6];
  inv[6] = -m[0] * m[6] * m[15] + m[0] * m[7] * m[14] + m[4] * m[2] * m[15] - m[4] * m[3] * m[14] - m[12] * m[2] * m[7] + m[12] * m[3] * m[6];
  inv[10] = m[0] * m[5] * m[15] - m[0] * m[7] * m[13] - m[4] * m[1] * m[15] + m[4] * m[3] * m[13] + m[12] * m[1] * m[7] - m[12] * m[3] * m[5];
  inv[14] = -m[0] * m[5] * m[14] + m[0] * m[6] * m[13] + m[4] * m[1] * m[14] - m[4] * m[2] * m[13] - m[12] * m[1] * m[6] + m[12] * m[2] * m[5];
  inv[3] = -m[1] * m[6] * m[11] + m[1] * m[7] * m[10] + m[5] * m[2] * m[11] - m[5] * m[3] * m[10] - m[9] * m[2] * m[7] + m[9] * m[3] * m[6];
  inv[7] = m[0] * m[6] * m[11] - m[0] * m[7] * m[10] - m[4] * m[2] * m[11] + m[4] * m[3] * m[10] + m[8] * m[2] * m[7] - m[8] * m[3] * m[6];
  inv[11] = -m[0] * m[5] * m[11] + m[0] * m[7] * m[9] + m[4] * m[1] * m[11] - m[4] * m[3] * m[9] - m[8] * m[1] * m[7] + m[8] * m[3] * m[5];
  inv[15] = m[0] * m[5] * m[10] - m[0] * m[6] * m[9] - m[4] * m[1] * m[10] + m[4] * m[2] * m[9] + m[8] * m[1] * m[6] - m[8] * m[2] * m[5];
  const double det = m[0] * inv[0] + m[1] * inv[4] + m[2] * inv[8] + m[3] * inv[12];
  M4 r;
  const double s = det != 0 ? 1.0 / det : 0.0;
  for (int i = 0; i < 16; ++i) r.m[i] = float(inv[i] * s);
  return r;
}

M4 translation(V3 t) {
  M4 r;
  r(0, 3) = t.x;
  r(1, 3) = t.y;
  r(2, 3) = t.z;
  return r;
}

M4 scaling(V3 s) {
  M4 r;
  r(0, 0) = s.x;
  r(1, 1) = s.y;
  r(2, 2) = s.z;
  return r;
}

M4 rotation(std::array<float, 4> q) {
  const float x = q[0], y = q[1], z = q[2], w = q[3];
  M4 r;
  r.m = {1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w), 0,
         2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w), 0,
         2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y), 0,
         0, 0, 0, 1};
  return r;
}

static std::array<float, 4> quatMul(std::array<float, 4> a, std::array<float, 4> b) {
  return {a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1], a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],
          a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3], a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2]};
}

std::array<float, 4> quatFromEulerDegrees(V3 deg) {
  auto axis = [](int i, float d) {
    const float h = d * kPi / 360.0f;
    std::array<float, 4> q{0, 0, 0, std::cos(h)};
    q[i] = std::sin(h);
    return q;
  };
  // X first, then Y, then Z: q = qz * qy * qx.
  return quatMul(axis(2, deg.z), quatMul(axis(1, deg.y), axis(0, deg.x)));
}

std::array<float, 4> slerp(std::array<float, 4> a, std::array<float, 4> b, float t) {
  float d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
  if (d < 0) {
    for (float& v : b) v = -v;
    d = -d;
  }
  std::array<float, 4> r;
  if (d > 0.9995f) {
    for (int i = 0; i < 4; ++i) r[i] = a[i] + (b[i] - a[i]) * t;
  } else {
    const float th = std::acos(d), s = std::sin(th);
    const float wa = std::sin((1 - t) * th) / s, wb = std::sin(t * th) / s;
    for (int i = 0; i < 4; ++i) r[i] = wa * a[i] + wb * b[i];
  }
  const float n = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + r[3] * r[3]);
  for (float& v : r) v /= n;
  return r;
}

// ---------------------------------------------------------------------------------------------
// Textures, meshes, animation, camera

V3 Texture::sample(float u, float v) const {
  const float fx = (u - std::floor(u)) * float(width) - 0.5f, fy = (v - std::floor(v)) * float(height) - 0.5f;
  const float flx = std::floor(fx), fly = std::floor(fy);
  const float tx = fx - flx, ty = fy - fly;
  // Repeat wrapping: fx, fy lie in [-0.5, size - 0.5), so only the edges wrap.
  int x0 = int(flx), y0 = int(fly);
  int x1 = x0 + 1, y1 = y0 + 1;
  if (x0 < 0) x0 += width;
  if (y0 < 0) y0 += height;
  if (x1 >= width) x1 -= width;
  if (y1 >= height) y1 -= height;
  const V3* r0 = texels.data() + size_t(y0) * width;
  const V3* r1 = texels.data() + size_t(y1) * width;
  return lerp(lerp(r0[x0], r0[x1], tx), lerp(r1[x0], r1[x1], tx), ty);
}

Mesh makeQuad() {
  Mesh m;
  m.positions = {{-0.5f, 0, -0.5f}, {0.5f, 0, -0.5f}, {0.5f, 0, 0.5f}, {-0.5f, 0, 0.5f}};
  m.normals.assign(4, V3(0, 1, 0));
  m.uvs = {0, 0, 1, 0, 1, 1, 0, 1};
  m.indices = {0, 2, 1, 0, 3, 2};
  return m;
}

Mesh makeBox() {
  Mesh m;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = -1; side <= 1; side += 2) {
      V3 n{0};
      n[axis] = float(side);
      V3 t{0}, b{0};
      t[(axis + 1) % 3] = 1;
      b[(axis + 2) % 3] = 1;
      if (side < 0) std::swap(t, b);  // keep the winding counter-clockwise seen from outside
      const uint32_t base = uint32_t(m.positions.size());
      const float corners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
      for (auto& c : corners) {
        m.positions.push_back(n * 0.5f + t * (0.5f * c[0]) + b * (0.5f * c[1]));
        m.normals.push_back(n);
        m.uvs.push_back(0.5f + 0.5f * c[0]);
        m.uvs.push_back(0.5f + 0.5f * c[1]);
      }
      for (uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) m.indices.push_back(base + i);
    }
  return m;
}

Mesh makeSphere(int segments, int rings) {
  Mesh m;
  m.analyticSphere = true;
  for (int r = 0; r <= rings; ++r) {
    const float th = kPi * float(r) / rings;
    for (int s = 0; s <= segments; ++s) {
      const float ph = 2 * kPi * float(s) / segments;
      const V3 n{std::sin(th) * std::cos(ph), std::cos(th), -std::sin(th) * std::sin(ph)};
      m.positions.push_back(n * 0.5f);
      m.normals.push_back(n);
      m.uvs.push_back(float(s) / segments);
      m.uvs.push_back(float(r) / rings);
    }
  }
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const uint32_t a = uint32_t(r * (segments + 1) + s), b = a + uint32_t(segments + 1);
      if (r != 0) m.indices.insert(m.indices.end(), {a, b, a + 1});
      if (r != rings - 1) m.indices.insert(m.indices.end(), {a + 1, b, b + 1});
    }
  return m;
}

Mesh makeCylinder(int segments) {
  Mesh m;
  for (int s = 0; s <= segments; ++s) {
    const float ph = 2 * kPi * float(s) / segments;
    const V3 n{std::cos(ph), 0, -std::sin(ph)};
    for (float y : {-0.5f, 0.5f}) {
      m.positions.push_back(n * 0.5f + V3(0, y, 0));
      m.normals.push_back(n);
      m.uvs.push_back(float(s) / segments);
      m.uvs.push_back(0.5f - y);
    }
  }
  for (int s = 0; s < segments; ++s) {
    const uint32_t a = uint32_t(2 * s);
    m.indices.insert(m.indices.end(), {a, a + 2, a + 1, a + 1, a + 2, a + 3});
  }
  for (float y : {-0.5f, 0.5f}) {
    const V3 n{0, y > 0 ? 1.0f : -1.0f, 0};
    const uint32_t centre = uint32_t(m.positions.size());
    m.positions.push_back({0, y, 0});
    m.normals.push_back(n);
    m.uvs.insert(m.uvs.end(), {0.5f, 0.5f});
    for (int s = 0; s <= segments; ++s) {
      const float ph = 2 * kPi * float(s) / segments;
      m.positions.push_back({0.5f * std::cos(ph), y, -0.5f * std::sin(ph)});
      m.normals.push_back(n);
      m.uvs.insert(m.uvs.end(), {0.5f + 0.5f * std::cos(ph), 0.5f + 0.5f * std::sin(ph)});
    }
    for (int s = 0; s < segments; ++s) {
      const uint32_t a = centre + 1 + uint32_t(s);
      if (y > 0) m.indices.insert(m.indices.end(), {centre, a, a + 1});
      else m.indices.insert(m.indices.end(), {centre, a + 1, a});
    }
  }
  return m;
}

M4 Object::worldAt(float t) const {
  if (keys.empty()) return base;
  if (keys.size() == 1 || t <= keys.front().frame) return keys.front().matrix() * base;
  if (t >= keys.back().frame) return keys.back().matrix() * base;
  size_t i = 1;
  while (keys[i].frame < t) ++i;
  const TransformKey &a = keys[i - 1], &b = keys[i];
  const float u = (t - a.frame) / std::max(1e-6f, b.frame - a.frame);
  TransformKey k;
  k.translation = lerp(a.translation, b.translation, u);
  k.rotation = slerp(a.rotation, b.rotation, u);
  k.scale = lerp(a.scale, b.scale, u);
  return k.matrix() * base;
}

float Object::emissionAt(float t) const {
  if (keys.empty()) return 1.0f;
  if (keys.size() == 1 || t <= keys.front().frame) return keys.front().emission;
  if (t >= keys.back().frame) return keys.back().emission;
  size_t i = 1;
  while (keys[i].frame < t) ++i;
  const TransformKey &a = keys[i - 1], &b = keys[i];
  const float u = (t - a.frame) / std::max(1e-6f, b.frame - a.frame);
  return a.emission + (b.emission - a.emission) * u;
}

static V3 catmullRomSpline(V3 p0, V3 p1, V3 p2, V3 p3, float t) {
  const float t2 = t * t, t3 = t2 * t;
  return (p1 * 2.0f + (p2 - p0) * t + (p0 * 2.0f - p1 * 5.0f + p2 * 4.0f - p3) * t2 + (p1 * 3.0f - p0 - p2 * 3.0f + p3) * t3) * 0.5f;
}

CameraKey SceneData::cameraAt(float t) const {
  if (cameraKeys.empty()) return CameraKey{};
  if (cameraKeys.size() == 1 || t <= cameraKeys.front().frame) return cameraKeys.front();
  if (t >= cameraKeys.back().frame) return cameraKeys.back();
  size_t i = 1;
  while (cameraKeys[i].frame < t) ++i;
  const CameraKey &a = cameraKeys[i - 1], &b = cameraKeys[i];
  const float u = (t - a.frame) / std::max(1e-6f, b.frame - a.frame);
  CameraKey k;
  k.frame = t;
  k.fovY = a.fovY + (b.fovY - a.fovY) * u;
  k.up = normalize(lerp(a.up, b.up, u));
  if (catmullRom) {
    const CameraKey& p = cameraKeys[i >= 2 ? i - 2 : 0];
    const CameraKey& n = cameraKeys[std::min(i + 1, cameraKeys.size() - 1)];
    k.position = catmullRomSpline(p.position, a.position, b.position, n.position, u);
    k.target = catmullRomSpline(p.target, a.target, b.target, n.target, u);
  } else {
    k.position = lerp(a.position, b.position, u);
    k.target = lerp(a.target, b.target, u);
  }
  return k;
}

View SceneData::viewAt(float t, float aspect, Eye eye, float eyeDistance) const {
  const CameraKey k = cameraAt(t);
  View v;
  v.forward = normalize(k.target - k.position);
  v.right = normalize(cross(v.forward, k.up));
  v.up = cross(v.right, v.forward);
  v.eye = k.position;
  if (eye == Eye::Left) v.eye = v.eye - v.right * (0.5f * eyeDistance);
  if (eye == Eye::Right) v.eye = v.eye + v.right * (0.5f * eyeDistance);
  v.tanHalfFovY = std::tan(k.fovY * kPi / 360.0f);
  v.aspect = aspect;
  return v;
}

M4 View::worldToCamera() const {
  M4 m;
  // Rows are the camera axes: x = right, y = up, z = -forward (camera looks down -Z).
  const V3 z = -forward;
  m.m = {right.x, right.y, right.z, -dot(right, eye), up.x, up.y, up.z, -dot(up, eye),
         z.x, z.y, z.z, -dot(z, eye), 0, 0, 0, 1};
  return m;
}

M4 View::projection() const {
  const float f = 1.0f / tanHalfFovY, n = nearPlane, fa = farPlane;
  M4 p;
  p.m = {f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, -(fa + n) / (fa - n), -2 * fa * n / (fa - n), 0, 0, -1, 0};
  return p;
}

bool SceneData::anyAnimated() const {
  for (const Object& o : objects)
    if (o.animated()) return true;
  return false;
}

std::string hashHex(const std::string& text) {
  uint64_t h = 1469598103934665603ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

std::string SceneData::contentHash() const { return hashHex(hashText); }

// ---------------------------------------------------------------------------------------------
// JSON scene description

namespace {

/// Reads typed fields with errors that name the file and the field path.
struct Reader {
  std::string source;

  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw Error("scene '" + source + "': field '" + field + "': " + what);
  }
  void allowOnly(const json& j, const std::string& path, std::initializer_list<const char*> keys) const {
    if (!j.is_object()) fail(path, "must be an object");
    std::set<std::string> allowed(keys.begin(), keys.end());
    for (auto it = j.begin(); it != j.end(); ++it)
      if (!allowed.count(it.key())) {
        std::string list;
        for (const auto& k : allowed) list += (list.empty() ? "" : ", ") + k;
        fail(join(path, it.key()), "unknown field (expected one of: " + list + ")");
      }
  }
  static std::string join(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }

  float number(const json& j, const std::string& field) const {
    if (!j.is_number()) fail(field, "must be a number");
    const double v = j.get<double>();
    if (!std::isfinite(v)) fail(field, "must be finite");
    return float(v);
  }
  float getFloat(const json& o, const std::string& path, const char* key, float def, float lo = -1e30f, float hi = 1e30f) const {
    if (!o.contains(key)) return def;
    const float v = number(o[key], join(path, key));
    if (v < lo || v > hi) fail(join(path, key), "must be in [" + fmt(lo) + ", " + fmt(hi) + "] (got " + fmt(v) + ")");
    return v;
  }
  int getInt(const json& o, const std::string& path, const char* key, int def, int lo, int hi) const {
    if (!o.contains(key)) return def;
    const json& j = o[key];
    if (!j.is_number_integer()) fail(join(path, key), "must be an integer");
    const long long v = j.get<long long>();
    if (v < lo || v > hi) fail(join(path, key), "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "] (got " + std::to_string(v) + ")");
    return int(v);
  }
  bool getBool(const json& o, const std::string& path, const char* key, bool def) const {
    if (!o.contains(key)) return def;
    if (!o[key].is_boolean()) fail(join(path, key), "must be true or false");
    return o[key].get<bool>();
  }
  std::string getString(const json& o, const std::string& path, const char* key, const std::string& def) const {
    if (!o.contains(key)) return def;
    if (!o[key].is_string()) fail(join(path, key), "must be a string");
    return o[key].get<std::string>();
  }
  /// A 3-vector, or a single number meaning (v, v, v).
  V3 vec3(const json& j, const std::string& field) const {
    if (j.is_number()) return V3(number(j, field));
    if (!j.is_array() || j.size() != 3) fail(field, "must be an array of 3 numbers");
    return {number(j[0], field + "[0]"), number(j[1], field + "[1]"), number(j[2], field + "[2]")};
  }
  V3 getV3(const json& o, const std::string& path, const char* key, V3 def) const {
    return o.contains(key) ? vec3(o[key], join(path, key)) : def;
  }
  V3 getColor(const json& o, const std::string& path, const char* key, V3 def) const {
    const V3 c = getV3(o, path, key, def);
    if (c.x < 0 || c.y < 0 || c.z < 0) fail(join(path, key), "colours must not be negative");
    return c;
  }
  static std::string fmt(float v) {
    char b[32];
    std::snprintf(b, sizeof b, "%g", double(v));
    return b;
  }
};

int checkerTexture(SceneData& s, V3 a, V3 b, int cells) {
  Texture t;
  t.width = t.height = 256;
  t.texels.resize(256 * 256);
  V3 sum{0};
  for (int y = 0; y < 256; ++y)
    for (int x = 0; x < 256; ++x) {
      const bool odd = ((x * cells / 256) + (y * cells / 256)) & 1;
      t.texels[size_t(y) * 256 + x] = odd ? b : a;
      sum += t.texels[size_t(y) * 256 + x];
    }
  t.mean = sum / float(256 * 256);
  s.textures.push_back(std::move(t));
  return int(s.textures.size()) - 1;
}

Material parseMaterial(const Reader& r, const json& j, const std::string& path, SceneData& s) {
  r.allowOnly(j, path, {"name", "baseColor", "metallic", "roughness", "specular", "emissive", "checker", "pattern", "mirror"});
  Material m;
  m.name = r.getString(j, path, "name", "");
  m.baseColor = r.getColor(j, path, "baseColor", m.baseColor);
  m.metallic = r.getFloat(j, path, "metallic", m.metallic, 0, 1);
  m.roughness = r.getFloat(j, path, "roughness", m.roughness, 0, 1);
  m.specular = r.getFloat(j, path, "specular", m.specular, 0, 1);
  m.emissive = r.getColor(j, path, "emissive", m.emissive);
  if (r.getBool(j, path, "mirror", false)) {
    m.metallic = 1;
    m.roughness = 0;
  }
  if (j.contains("checker")) {
    const std::string cp = path + ".checker";
    const json& c = j["checker"];
    r.allowOnly(c, cp, {"color", "cells"});
    const V3 other = r.getColor(c, cp, "color", V3(0.2f));
    const int cells = r.getInt(c, cp, "cells", 8, 1, 128);
    m.baseColorTexture = checkerTexture(s, m.baseColor, other, cells);
  }
  if (j.contains("pattern")) {  // procedural patterns (src/render/procedural.cpp)
    const std::string pp = path + ".pattern";
    const json& c = j["pattern"];
    r.allowOnly(c, pp, {"kind", "color", "cells", "seed"});
    const std::string kind = r.getString(c, pp, "kind", "");
    const auto pattern = patternFromName(kind);
    if (!pattern) r.fail(pp + ".kind", "unknown pattern '" + kind + "' (expected " + patternNames() + ")");
    const V3 other = r.getColor(c, pp, "color", V3(0.2f));
    const int cells = r.getInt(c, pp, "cells", 8, 1, 128);
    const int seed = r.getInt(c, pp, "seed", 0, 0, 2147483647);
    s.textures.push_back(makePatternTexture(*pattern, m.baseColor, other, cells, uint32_t(seed)));
    m.baseColorTexture = int(s.textures.size()) - 1;
  }
  return m;
}

std::array<float, 4> parseRotation(const Reader& r, const json& j, const std::string& field) {
  // Euler angles in degrees [x, y, z] (applied X, Y, Z) or a quaternion [x, y, z, w].
  if (j.is_array() && j.size() == 4) {
    std::array<float, 4> q;
    for (int i = 0; i < 4; ++i) q[i] = r.number(j[i], field);
    const float n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (n <= 0) r.fail(field, "a quaternion must not be zero");
    for (float& v : q) v /= n;
    return q;
  }
  return quatFromEulerDegrees(r.vec3(j, field));
}

TransformKey parseTransform(const Reader& r, const json& j, const std::string& path, const TransformKey& def) {
  TransformKey k = def;
  k.frame = r.getFloat(j, path, "frame", def.frame, 0);
  k.translation = r.getV3(j, path, "translation", def.translation);
  if (j.contains("rotation")) k.rotation = parseRotation(r, j["rotation"], path + ".rotation");
  k.scale = r.getV3(j, path, "scale", def.scale);
  k.emission = r.getFloat(j, path, "emission", def.emission, 0);
  return k;
}

std::vector<TransformKey> parseKeys(const Reader& r, const json& j, const std::string& path, const TransformKey& start) {
  if (!j.is_array() || j.empty()) r.fail(path, "must be a non-empty array of keyframes");
  std::vector<TransformKey> keys;
  TransformKey prev = start;
  for (size_t i = 0; i < j.size(); ++i) {
    const std::string p = path + "[" + std::to_string(i) + "]";
    r.allowOnly(j[i], p, {"frame", "translation", "rotation", "scale", "emission"});
    if (!j[i].contains("frame")) r.fail(p + ".frame", "missing (every keyframe needs its frame index)");
    prev = parseTransform(r, j[i], p, prev);  // unspecified fields carry over from the previous key
    if (!keys.empty() && prev.frame <= keys.back().frame) r.fail(p + ".frame", "keyframes must have increasing frames");
    keys.push_back(prev);
  }
  return keys;
}

int meshForShape(const Reader& r, const std::string& shape, const std::string& field, SceneData& s) {
  static const char* kShapes[] = {"quad", "box", "sphere", "cylinder"};
  Mesh m;
  if (shape == "quad") m = makeQuad();
  else if (shape == "box") m = makeBox();
  else if (shape == "sphere") m = makeSphere();
  else if (shape == "cylinder") m = makeCylinder();
  else {
    std::string list;
    for (auto* k : kShapes) list += std::string(list.empty() ? "" : ", ") + k;
    r.fail(field, "unknown shape '" + shape + "' (expected " + list + ")");
  }
  s.meshes.push_back(std::move(m));
  return int(s.meshes.size()) - 1;
}

}  // namespace

void parseSceneJson(const std::string& text, const fs::path& baseDir, const std::string& source, SceneData& s) {
  Reader r{source};
  json j;
  try {
    j = json::parse(text);
  } catch (const std::exception& e) {
    throw Error("scene '" + source + "' is not valid JSON: " + e.what());
  }
  r.allowOnly(j, "", {"name", "frames", "resolution", "render", "gltf", "gltfTransform", "materials", "objects",
                      "animations", "camera", "sky", "sun", "comment"});
  s.source = source;
  s.name_ = r.getString(j, "", "name", fs::path(source).stem().string());
  s.frames = r.getInt(j, "", "frames", 1, 1, 1000000);
  if (j.contains("resolution")) {
    const json& res = j["resolution"];
    if (!res.is_array() || res.size() != 2 || !res[0].is_number_integer() || !res[1].is_number_integer() ||
        res[0].get<int>() < 1 || res[1].get<int>() < 1 || res[0].get<int>() > 16384 || res[1].get<int>() > 16384)
      r.fail("resolution", "must be [width, height], two integers in [1, 16384]");
    s.settings.width = res[0].get<int>();
    s.settings.height = res[1].get<int>();
  }
  if (j.contains("render")) {
    const json& o = j["render"];
    r.allowOnly(o, "render", {"spp", "maxDepth", "russianRouletteDepth", "seed", "pixelJitter", "eyeDistance"});
    s.settings.spp = r.getInt(o, "render", "spp", s.settings.spp, 1, 1 << 20);
    s.settings.maxDepth = r.getInt(o, "render", "maxDepth", s.settings.maxDepth, 1, 1024);
    s.settings.russianRouletteDepth = r.getInt(o, "render", "russianRouletteDepth", s.settings.russianRouletteDepth, 1, 1024);
    s.settings.seed = uint32_t(r.getInt(o, "render", "seed", int(s.settings.seed), 0, 2147483647));
    s.settings.pixelJitter = r.getBool(o, "render", "pixelJitter", s.settings.pixelJitter);
    s.settings.eyeDistance = r.getFloat(o, "render", "eyeDistance", s.settings.eyeDistance, 0);
  }

  if (j.contains("gltf")) {
    const std::string file = r.getString(j, "", "gltf", "");
    M4 root;
    if (j.contains("gltfTransform")) {
      r.allowOnly(j["gltfTransform"], "gltfTransform", {"translation", "rotation", "scale"});
      root = parseTransform(r, j["gltfTransform"], "gltfTransform", TransformKey{}).matrix();
    }
    const fs::path p = fs::path(file).is_absolute() ? fs::path(file) : baseDir / file;
    loadGltf(p, s, root, !j.contains("camera"));
  }

  // Named materials first, so objects can refer to them.
  std::map<std::string, int> named;
  for (size_t i = 0; i < s.materials.size(); ++i) named[s.materials[i].name] = int(i);
  if (j.contains("materials")) {
    const json& ms = j["materials"];
    if (!ms.is_object()) r.fail("materials", "must be an object mapping names to materials");
    for (auto it = ms.begin(); it != ms.end(); ++it) {
      Material m = parseMaterial(r, it.value(), "materials." + it.key(), s);
      m.name = it.key();
      s.materials.push_back(m);
      named[it.key()] = int(s.materials.size()) - 1;
    }
  }

  if (j.contains("objects")) {
    const json& os = j["objects"];
    if (!os.is_array()) r.fail("objects", "must be an array");
    for (size_t i = 0; i < os.size(); ++i) {
      const std::string p = "objects[" + std::to_string(i) + "]";
      const json& o = os[i];
      r.allowOnly(o, p, {"name", "shape", "material", "translation", "rotation", "scale", "animation"});
      Object obj;
      obj.name = r.getString(o, p, "name", "object" + std::to_string(i));
      if (!o.contains("shape")) r.fail(p + ".shape", "missing");
      obj.mesh = meshForShape(r, r.getString(o, p, "shape", ""), p + ".shape", s);
      if (!o.contains("material")) {
        s.materials.push_back(Material{});
        obj.material = int(s.materials.size()) - 1;
      } else if (o["material"].is_string()) {
        auto it = named.find(o["material"].get<std::string>());
        if (it == named.end()) r.fail(p + ".material", "no material named '" + o["material"].get<std::string>() + "'");
        obj.material = it->second;
      } else {
        s.materials.push_back(parseMaterial(r, o["material"], p + ".material", s));
        obj.material = int(s.materials.size()) - 1;
      }
      TransformKey rest = parseTransform(r, o, p, TransformKey{});
      rest.frame = 0;
      if (o.contains("animation")) obj.keys = parseKeys(r, o["animation"], p + ".animation", rest);
      else obj.base = rest.matrix();
      s.objects.push_back(obj);
    }
  }

  if (j.contains("animations")) {
    const json& as = j["animations"];
    if (!as.is_object()) r.fail("animations", "must be an object mapping object names to keyframe arrays");
    for (auto it = as.begin(); it != as.end(); ++it) {
      bool found = false;
      for (Object& o : s.objects)
        if (o.name == it.key()) {
          // Applied on top of the object's own transform (a glTF node's world matrix).
          o.keys = parseKeys(r, it.value(), "animations." + it.key(), TransformKey{});
          found = true;
        }
      if (!found) r.fail("animations." + it.key(), "no object or glTF node named '" + it.key() + "'");
    }
  }

  if (j.contains("camera")) {
    const json& c = j["camera"];
    r.allowOnly(c, "camera", {"fov", "interpolation", "keyframes", "position", "target", "up"});
    CameraKey def;
    def.fovY = r.getFloat(c, "camera", "fov", def.fovY, 1, 179);
    def.position = r.getV3(c, "camera", "position", def.position);
    def.target = r.getV3(c, "camera", "target", def.target);
    def.up = r.getV3(c, "camera", "up", def.up);
    const std::string interp = r.getString(c, "camera", "interpolation", "linear");
    if (interp != "linear" && interp != "catmull-rom") r.fail("camera.interpolation", "must be \"linear\" or \"catmull-rom\"");
    s.catmullRom = interp == "catmull-rom";
    s.cameraKeys.clear();
    if (c.contains("keyframes")) {
      const json& ks = c["keyframes"];
      if (!ks.is_array() || ks.empty()) r.fail("camera.keyframes", "must be a non-empty array");
      CameraKey prev = def;
      for (size_t i = 0; i < ks.size(); ++i) {
        const std::string p = "camera.keyframes[" + std::to_string(i) + "]";
        r.allowOnly(ks[i], p, {"frame", "position", "target", "up", "fov"});
        if (!ks[i].contains("frame")) r.fail(p + ".frame", "missing (every keyframe needs its frame index)");
        CameraKey k = prev;
        k.frame = r.getFloat(ks[i], p, "frame", 0, 0);
        k.position = r.getV3(ks[i], p, "position", prev.position);
        k.target = r.getV3(ks[i], p, "target", prev.target);
        k.up = r.getV3(ks[i], p, "up", prev.up);
        k.fovY = r.getFloat(ks[i], p, "fov", prev.fovY, 1, 179);
        if (!s.cameraKeys.empty() && k.frame <= s.cameraKeys.back().frame) r.fail(p + ".frame", "keyframes must have increasing frames");
        if (length(k.target - k.position) <= 0) r.fail(p + ".target", "must differ from the position");
        s.cameraKeys.push_back(k);
        prev = k;
      }
    } else {
      if (length(def.target - def.position) <= 0) r.fail("camera.target", "must differ from the position");
      s.cameraKeys.push_back(def);
    }
  }

  if (j.contains("sky")) {
    const json& k = j["sky"];
    r.allowOnly(k, "sky", {"color", "zenith", "horizon", "ground"});
    const V3 c = r.getColor(k, "sky", "color", V3(0));
    s.sky.zenith = r.getColor(k, "sky", "zenith", c);
    s.sky.horizon = r.getColor(k, "sky", "horizon", c);
    s.sky.ground = r.getColor(k, "sky", "ground", k.contains("color") ? c : s.sky.horizon);
  }
  if (j.contains("sun")) {
    const json& k = j["sun"];
    r.allowOnly(k, "sun", {"direction", "irradiance", "angle"});
    const V3 d = r.getV3(k, "sun", "direction", V3(0, 1, 0));
    if (length(d) <= 0) r.fail("sun.direction", "must not be zero");
    s.sun.direction = normalize(d);
    s.sun.irradiance = r.getColor(k, "sun", "irradiance", V3(0));
    s.sun.angleDegrees = r.getFloat(k, "sun", "angle", 0.0f, 0, 45);
  }
  if (s.cameraKeys.empty()) s.cameraKeys.push_back(CameraKey{});
  if (s.objects.empty() && !s.sky.enabled() && !s.sun.enabled())
    throw Error("scene '" + source + "': nothing to render (no objects, no sky, no sun)");
  s.hashText += text;
}

std::shared_ptr<Scene> Scene::fromJson(const std::string& text, const fs::path& baseDir, const std::string& sourceName) {
  auto s = std::make_shared<SceneData>();
  parseSceneJson(text, baseDir, sourceName, *s);
  return s;
}

std::shared_ptr<Scene> Scene::load(const std::string& nameOrPath) {
  if (auto builtin = builtinSceneJson(nameOrPath)) return fromJson(*builtin, fs::current_path(), nameOrPath);
  if (nameOrPath.rfind(kProceduralPrefix, 0) == 0) {  // "procedural:<seed>[:<frames>]"
    const std::string rest = nameOrPath.substr(std::string(kProceduralPrefix).size());
    unsigned long seed = 0, frames = ProceduralOptions{}.frames;
    char tail = 0;
    const int n = std::sscanf(rest.c_str(), "%lu:%lu%c", &seed, &frames, &tail);
    if (n < 1 || n > 2 || seed > 0xFFFFFFFFul || frames < 1 || frames > 100000 || rest.find_first_not_of("0123456789:") != std::string::npos)
      throw Error("scene '" + nameOrPath + "': expected procedural:<seed> or procedural:<seed>:<frames>");
    ProceduralOptions opt;
    opt.frames = int(frames);
    return fromJson(proceduralSceneJson(uint32_t(seed), opt), fs::current_path(), nameOrPath);
  }
  const fs::path p(nameOrPath);
  std::string ext = p.extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (ext != ".json" && ext != ".gltf" && ext != ".glb") {
    std::string list;
    for (const auto& n : builtinScenes()) list += (list.empty() ? "" : ", ") + n;
    throw Error("scene '" + nameOrPath + "': neither a built-in scene (" + list + ") nor a .json/.gltf/.glb file");
  }
  if (!fs::exists(p)) throw Error("scene '" + nameOrPath + "': file not found");
  auto s = std::make_shared<SceneData>();
  if (ext == ".json") {
    std::ifstream in(p);
    if (!in) throw Error("scene '" + nameOrPath + "': cannot open the file");
    std::stringstream ss;
    ss << in.rdbuf();
    parseSceneJson(ss.str(), p.parent_path(), nameOrPath, *s);
    return s;
  }
  s->source = nameOrPath;
  s->name_ = p.stem().string();
  loadGltf(p, *s, M4{}, true);
  if (s->cameraKeys.empty()) s->cameraKeys.push_back(CameraKey{});
  // A glTF file alone has no lights beyond its emissive materials: add a soft sky so it is lit.
  s->sky.zenith = V3(0.6f, 0.7f, 0.9f);
  s->sky.horizon = V3(0.9f, 0.9f, 0.9f);
  s->sky.ground = V3(0.3f);
  s->hashText += "sky-default";
  return s;
}

}  // namespace rtd::render
