// Small vector/matrix helpers for the path tracer (float, scalar code; Embree does the heavy part).
#pragma once
#include <algorithm>
#include <array>
#include <cmath>

namespace rtd::render {

constexpr float kPi = 3.14159265358979323846f;
constexpr float kInvPi = 1.0f / kPi;

struct V3 {
  float x = 0, y = 0, z = 0;
  constexpr V3() = default;
  constexpr V3(float a, float b, float c) : x(a), y(b), z(c) {}
  constexpr explicit V3(float a) : x(a), y(a), z(a) {}
  float operator[](int i) const { return i == 0 ? x : i == 1 ? y : z; }
  float& operator[](int i) { return i == 0 ? x : i == 1 ? y : z; }
};
inline V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline V3 operator-(V3 a) { return {-a.x, -a.y, -a.z}; }
inline V3 operator*(V3 a, V3 b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
inline V3 operator*(V3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
inline V3 operator*(float s, V3 a) { return {a.x * s, a.y * s, a.z * s}; }
inline V3 operator/(V3 a, float s) { return a * (1.0f / s); }
inline V3& operator+=(V3& a, V3 b) { return a = a + b; }
inline V3& operator*=(V3& a, V3 b) { return a = a * b; }
inline V3& operator*=(V3& a, float s) { return a = a * s; }
inline float dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline float length(V3 a) { return std::sqrt(dot(a, a)); }
inline V3 normalize(V3 a) {
  const float l = length(a);
  return l > 0 ? a / l : V3(0, 0, 1);
}
inline V3 lerp(V3 a, V3 b, float t) { return a + (b - a) * t; }
inline float maxComponent(V3 a) { return std::max(a.x, std::max(a.y, a.z)); }
inline float luminance(V3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }
inline V3 reflect(V3 d, V3 n) { return d - n * (2.0f * dot(d, n)); }

/// Orthonormal basis around a unit vector (Duff et al. 2017, branchless).
inline void basis(V3 n, V3& t, V3& b) {
  const float s = std::copysign(1.0f, n.z);
  const float a = -1.0f / (s + n.z);
  const float c = n.x * n.y * a;
  t = {1.0f + s * n.x * n.x * a, s * c, -s * n.x};
  b = {c, s + n.y * n.y * a, -n.y};
}

/// Row-major 4x4 matrix acting on column vectors (p' = M p), as rtd::Camera.
struct M4 {
  std::array<float, 16> m{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  float operator()(int r, int c) const { return m[r * 4 + c]; }
  float& operator()(int r, int c) { return m[r * 4 + c]; }
  V3 point(V3 p) const {
    return {m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3], m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7],
            m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11]};
  }
  V3 vector(V3 v) const {
    return {m[0] * v.x + m[1] * v.y + m[2] * v.z, m[4] * v.x + m[5] * v.y + m[6] * v.z,
            m[8] * v.x + m[9] * v.y + m[10] * v.z};
  }
  /// Transforms a normal with the inverse transpose given as `inverse` (normals: n' = M^-T n).
  static V3 normal(const M4& inverse, V3 n) {
    const auto& a = inverse.m;
    return {a[0] * n.x + a[4] * n.y + a[8] * n.z, a[1] * n.x + a[5] * n.y + a[9] * n.z,
            a[2] * n.x + a[6] * n.y + a[10] * n.z};
  }
};

inline M4 operator*(const M4& a, const M4& b) {
  M4 r;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += double(a(i, k)) * b(k, j);
      r(i, j) = float(s);
    }
  return r;
}

/// General 4x4 inverse (cofactors, double precision).
M4 inverse(const M4& a);
M4 translation(V3 t);
M4 scaling(V3 s);
/// Rotation from a unit quaternion (x, y, z, w).
M4 rotation(std::array<float, 4> q);
/// Quaternion from Euler angles in degrees, applied X then Y then Z.
std::array<float, 4> quatFromEulerDegrees(V3 deg);
std::array<float, 4> slerp(std::array<float, 4> a, std::array<float, 4> b, float t);

}  // namespace rtd::render
