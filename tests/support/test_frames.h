// Small helpers to build frames by hand in tests.
#pragma once
#include <cmath>

#include "core/frame_data.h"
#include "rtd/rtd.h"

namespace rtd::test {

/// A frame of constant buffers: colour c (grey), depth z, normal +z, object id, zero motion.
inline Frame flatFrame(int w, int h, float color, float depth = 1.0f, float id = 1.0f) {
  Frame f;
  f.width = w;
  f.height = h;
  f[Buffer::Color] = Image(w, h, 3, color);
  f[Buffer::Depth] = Image(w, h, 1, depth);
  f[Buffer::Normal] = Image(w, h, 3, 0.0f);
  for (int i = 0; i < w * h; ++i) f[Buffer::Normal].pixels[size_t(i) * 3 + 2] = 1.0f;
  f[Buffer::ObjectId] = Image(w, h, 1, id);
  f[Buffer::Motion] = Image(w, h, 2, 0.0f);
  return f;
}

/// The CPU backend's view of a frame (all buffers as planes).
inline FrameData toFrameData(const Frame& f) {
  FrameData d;
  importFrame(f.inputs(), {Buffer::Color}, d);
  return d;
}

inline bool allFinite(const Image& img) {
  for (float v : img.pixels)
    if (!std::isfinite(v)) return false;
  return true;
}

}  // namespace rtd::test
