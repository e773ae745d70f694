// Small helpers to build frames by hand in tests.
#pragma once
#include <algorithm>
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

/// Largest |a - e| / (1 + |e|) over the RGB values (the learned methods' cross-checks).
inline double maxRelativeError(const Image& a, const Image& e) {
  double m = 0;
  for (int y = 0; y < e.height; ++y)
    for (int x = 0; x < e.width; ++x)
      for (int c = 0; c < 3; ++c)
        m = std::max(m, std::abs(double(a.at(x, y, c)) - e.at(x, y, c)) / (1.0 + std::abs(double(e.at(x, y, c)))));
  return m;
}

/// An image from a planar [channel][y][x] array (numbers, as the PyTorch fixtures write them:
/// python/rtdenoise_train/fixture.py); the channel count is the array's size / (w h).
template <class Json> Image planarImage(const Json& a, int w, int h) {
  const int channels = int(a.size()) / (w * h);
  Image img(w, h, channels);
  for (int c = 0; c < channels; ++c)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) img.at(x, y, c) = a[(size_t(c) * h + y) * w + x].template get<float>();
  return img;
}

inline bool allFinite(const Image& img) {
  for (float v : img.pixels)
    if (!std::isfinite(v)) return false;
  return true;
}

/// `d` run on frame `f`: its RGB output.
inline Image denoised(Denoiser& d, const Frame& f) {
  Image out(f.width, f.height, 3);
  d.denoise(f.inputs(), out.view());
  return out;
}

/// Root mean square difference over every float of two images of the same size and channels.
inline double rmse(const Image& a, const Image& b) {
  double e = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i) e += (double(a.pixels[i]) - b.pixels[i]) * (double(a.pixels[i]) - b.pixels[i]);
  return std::sqrt(e / double(a.pixels.size()));
}

}  // namespace rtd::test
