#include "passes/taa_keys.h"

#include "core/parallel.h"
#include "passes/emitters.h"
#include "passes/reflection_reprojection.h"

namespace rtd {

bool taaSurfaceKeys(const FrameData& f, const EmitterSettings* emitters, const PixelVector<uint8_t>* cls,
                    PixelVector<uint32_t>& out) {
  const int w = f.width, h = f.height;
  const float* id = f.has(Buffer::ObjectId) ? f.plane(Buffer::ObjectId).ptr() : nullptr;
  // The emitters the filter leaves out (excludeEmitters(): all of them with the setting on,
  // the reflectanceless ones with it off).
  const bool emission = emitters && f.has(Buffer::Emission) && (emitters->excludeEmitters || f.has(Buffer::Albedo));
  if (!id && !cls && !emission) return false;
  out.resize(size_t(w) * h);
  const std::vector<Plane>* e = emission ? &f.planes(Buffer::Emission) : nullptr;
  const std::vector<Plane>* a = emission && !emitters->excludeEmitters ? &f.planes(Buffer::Albedo) : nullptr;
  parallelRows(h, [&](int y) {
    if (!e && !cls) {  // object ids alone (the common case), in a loop that vectorizes
      const float* row = id + size_t(y) * w;
      uint32_t* o = out.data() + size_t(y) * w;
      for (int x = 0; x < w; ++x) o[x] = surfaceKey(row[x], 0) & ~kTaaEmitterKey;
      return;
    }
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      uint32_t key = surfaceKey(id ? id[i] : 0.0f, cls ? (*cls)[i] : uint8_t(0)) & ~kTaaEmitterKey;
      if (e && emitterPixel((*e)[0].ptr()[i], (*e)[1].ptr()[i], (*e)[2].ptr()[i], emitters->emitterThreshold) &&
          (!a || reflectanceless((*a)[0].ptr()[i], (*a)[1].ptr()[i], (*a)[2].ptr()[i])))
        key |= kTaaEmitterKey;
      out[i] = key;
    }
  });
  return true;
}

}  // namespace rtd
