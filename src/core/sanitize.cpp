#include "core/sanitize.h"

#include <atomic>

#include "core/frame_data.h"
#include "core/parallel.h"

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

void sanitizeUnitVectors(FrameData& f, SanitizeStats& counts) {
  for (int i = 0; i < kBufferCount; ++i) {
    const Buffer b = Buffer(i);
    if (!isUnitVectorBuffer(b) || !f.has(b)) continue;
    std::atomic<uint64_t> changed{0};
    parallelRows(f.height, [&](int y) {
      float* px = f.plane(b, 0).row(y);
      float* py = f.plane(b, 1).row(y);
      float* pz = f.plane(b, 2).row(y);
      // Valid rows (the common case) only pay for this vectorizable test.
      bool any = false;
      for (int x = 0; x < f.width; ++x) {
        const float l2 = px[x] * px[x] + py[x] * py[x] + pz[x] * pz[x];
        any |= (std::abs(l2 - 1.0f) > kUnitLengthTolerance) & ((px[x] != 0.0f) | (py[x] != 0.0f) | (pz[x] != 0.0f));
      }
      if (!any) return;
      uint64_t n = 0;
      for (int x = 0; x < f.width; ++x) n += renormalize(px[x], py[x], pz[x]);
      if (n) changed += n;
    }, 16);
    counts[size_t(i)].renormalized += changed;
  }
}

}  // namespace rtd
