// A single float channel of an image: the CPU backend keeps every buffer as structure-of-arrays
// planes so inner loops over a row vectorize (see shared/notes/cpu-performance.md).
#pragma once
#include <array>
#include <cstddef>
#include <vector>

namespace rtd {

struct Plane {
  int width = 0;
  int height = 0;
  std::vector<float> data;

  Plane() = default;
  Plane(int w, int h, float fill = 0.0f) : width(w), height(h), data(size_t(w) * h, fill) {}

  void resize(int w, int h, float fill = 0.0f) {
    width = w;
    height = h;
    data.assign(size_t(w) * h, fill);
  }
  void fill(float v) { std::fill(data.begin(), data.end(), v); }
  bool empty() const { return data.empty(); }
  size_t size() const { return data.size(); }
  float* row(int y) { return data.data() + size_t(y) * width; }
  const float* row(int y) const { return data.data() + size_t(y) * width; }
  float& operator()(int x, int y) { return data[size_t(y) * width + x]; }
  float operator()(int x, int y) const { return data[size_t(y) * width + x]; }
  float* ptr() { return data.data(); }
  const float* ptr() const { return data.data(); }
};

/// Three planes: RGB radiance or an XYZ vector field.
using Plane3 = std::array<Plane, 3>;

inline void resize(Plane3& p, int w, int h, float fill = 0.0f) {
  for (auto& c : p) c.resize(w, h, fill);
}

/// Rec. 709 / sRGB-primaries luminance of linear RGB.
inline float luminance(float r, float g, float b) { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }

}  // namespace rtd
