#include "passes/demodulation.h"

#include <algorithm>

#include "core/parallel.h"

namespace rtd {

void demodulate(const std::vector<Plane>& radiance, const std::vector<Plane>* albedo, Plane3& out) {
  const int w = radiance[0].width;
  for (int c = 0; c < 3; ++c)
    if (out[c].width != w || out[c].height != radiance[0].height) out[c].resize(w, radiance[0].height);
  parallelRows(radiance[0].height, [&](int y) {
    for (int c = 0; c < 3; ++c) {
      const float* in = radiance[c].row(y);
      float* o = out[c].row(y);
      if (!albedo) {
        std::copy(in, in + w, o);
        continue;
      }
      const float* a = (*albedo)[c].row(y);
      for (int x = 0; x < w; ++x) o[x] = in[x] / demodulationFactor(a[x]);
    }
  });
}

void remodulateSpan(const float* in, const float* albedo, float* out, int n) {
  if (!albedo) {
    if (out != in) std::copy(in, in + n, out);
    return;
  }
  for (int x = 0; x < n; ++x) out[x] = in[x] * demodulationFactor(albedo[x]);
}

void remodulateRow(const Plane3& illumination, const std::vector<Plane>* albedo, Plane3& out, int y) {
  for (int c = 0; c < 3; ++c)
    remodulateSpan(illumination[c].row(y), albedo ? (*albedo)[c].row(y) : nullptr, out[c].row(y), illumination[0].width);
}

void remodulate(Plane3& illumination, const std::vector<Plane>* albedo) {
  if (!albedo) return;
  parallelRows(illumination[0].height, [&](int y) { remodulateRow(illumination, albedo, illumination, y); });
}

}  // namespace rtd
