#include "core/sanitize.h"


namespace rtd {

ValueRange importRange(Buffer b) {
  switch (b) {
    case Buffer::Color: case Buffer::Direct: case Buffer::Indirect: case Buffer::Diffuse:
    case Buffer::Specular: case Buffer::Emission: case Buffer::IndirectDiffuse:
    case Buffer::Albedo: case Buffer::ReflectedAlbedo:
    case Buffer::GradientPrevious: case Buffer::GradientCurrent: return {0.0f, kMaxRadiance};
    case Buffer::Depth: case Buffer::SecondaryDistance: return {0.0f, kMaxGuideMagnitude};
    case Buffer::Motion: return {-kMaxMotion, kMaxMotion};
    case Buffer::ObjectId: case Buffer::MaterialId: case Buffer::Seed: return {-kMaxId, kMaxId};
    case Buffer::Roughness: case Buffer::Metalness: case Buffer::SampleMask:
    case Buffer::GradientSample: case Buffer::HiddenArea: return {0.0f, 1.0f};
    default: return {-kMaxGuideMagnitude, kMaxGuideMagnitude};  // normals, positions, gradients, directions
  }
}

bool isUnitVectorBuffer(Buffer b) {
  return b == Buffer::Normal || b == Buffer::ReflectedNormal || b == Buffer::MirrorDirection;
}

uint64_t renormalizeRow(float* px, float* py, float* pz, int w) {
  bool any = false;
  for (int x = 0; x < w; ++x) {
    const float l2 = px[x] * px[x] + py[x] * py[x] + pz[x] * pz[x];
    any |= (std::abs(l2 - 1.0f) > kUnitLengthTolerance) & ((px[x] != 0.0f) | (py[x] != 0.0f) | (pz[x] != 0.0f));
  }
  if (!any) return 0;
  uint64_t n = 0;
  for (int x = 0; x < w; ++x) n += renormalize(px[x], py[x], pz[x]);
  return n;
}

}  // namespace rtd
