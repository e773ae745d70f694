/* The scene of the example programs (C99 and C++): a textured wall facing the camera, scrolling
 * right by one pixel per frame, rendered with 1-spp-like noise. Frame t, pixel (x, y):
 * clean radiance = albedo * light; the noisy colour multiplies it by an exponential variate of
 * mean 1; the motion to the previous frame is (-1, 0) pixels; normal +z; depth 5. */
#ifndef RTD_EXAMPLE_SCENE_H
#define RTD_EXAMPLE_SCENE_H

#include <math.h>

enum { kSceneWidth = 64, kSceneHeight = 48, kSceneFrames = 8 };

static inline float sceneAlbedo(int x, int y, int t) { return ((x - t + 64) / 8 + y / 8) % 2 ? 0.8f : 0.2f; }
static inline float sceneLight(int x, int y, int t) {
  return 1.0f + 0.5f * sinf(0.1f * (float)(x - t)) * cosf(0.13f * (float)y);
}
static inline float sceneNoise(int x, int y, int t) {
  unsigned h = (unsigned)x * 73856093u ^ (unsigned)y * 19349663u ^ (unsigned)t * 83492791u;
  h = (h ^ (h >> 13)) * 1274126177u;
  return -logf(((float)((h >> 8) & 0xffffffu) + 0.5f) / 16777216.0f);
}

/* Fills frame t's buffers (RGB colour, clean RGB, RGB albedo, RGB normal, depth, XY motion). */
static inline void sceneFrame(int t, float* color, float* clean, float* albedo, float* normal, float* depth, float* motion) {
  int x, y, c;
  for (y = 0; y < kSceneHeight; ++y)
    for (x = 0; x < kSceneWidth; ++x) {
      const int p = y * kSceneWidth + x;
      for (c = 0; c < 3; ++c) {
        albedo[p * 3 + c] = sceneAlbedo(x, y, t);
        clean[p * 3 + c] = sceneAlbedo(x, y, t) * sceneLight(x, y, t);
        color[p * 3 + c] = clean[p * 3 + c] * sceneNoise(x, y, t);
        normal[p * 3 + c] = c == 2 ? 1.0f : 0.0f; /* world space, facing the camera */
      }
      depth[p] = 5.0f;        /* linear view depth */
      motion[p * 2] = -1.0f;  /* the content of pixel x was at x - 1 in the previous frame */
      motion[p * 2 + 1] = 0.0f;
    }
}

/* RMSE of the first three channels of `image` (`stride` floats per pixel) against clean RGB. */
static inline double sceneRmse(const float* image, int stride, const float* clean) {
  double sum = 0;
  int p, c;
  for (p = 0; p < kSceneWidth * kSceneHeight; ++p)
    for (c = 0; c < 3; ++c) {
      const double d = (double)image[p * stride + c] - (double)clean[p * 3 + c];
      sum += d * d;
    }
  return sqrt(sum / (kSceneWidth * kSceneHeight * 3));
}

#endif
