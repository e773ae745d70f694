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
      for (int x = 0; x < w; ++x) {
        const float factor = demodulationFactor(a[x]), radianceX = in[x];  // named: see remodulateSpan
        o[x] = radianceX / factor;
      }
    }
  });
}

void remodulateSpan(const float* in, const float* albedo, float* out, int n) {
  if (!albedo) {
    if (out != in) std::copy(in, in + n, out);
    return;
  }
  // Both operands named before the product: written as in[x] * demodulationFactor(albedo[x]),
  // GCC moved the product into the select's one branch and left the loop scalar and branchy.
  for (int x = 0; x < n; ++x) {
    const float factor = demodulationFactor(albedo[x]), illumination = in[x];
    out[x] = illumination * factor;
  }
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
