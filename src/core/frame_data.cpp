#include "core/frame_data.h"

#include <algorithm>
#include <bit>
#include <atomic>
#include <cfloat>
#include <cmath>
#include <string>
#ifdef __AVX2__
#include <immintrin.h>
#endif

#include "core/flush.h"
#include "core/parallel.h"
#include "core/sanitize.h"
#include "core/validate.h"
#include "rtd/error.h"

namespace rtd {

bool isRadianceBuffer(Buffer b) {
  switch (b) {
    case Buffer::Color: case Buffer::Direct: case Buffer::Indirect:
    case Buffer::Diffuse: case Buffer::Specular: case Buffer::Emission: case Buffer::IndirectDiffuse:
    case Buffer::GradientPrevious: case Buffer::GradientCurrent: return true;
    default: return false;
  }
}

std::vector<Buffer> importedBuffers(const std::vector<Buffer>& required, const std::vector<Buffer>& extra,
                                    const ReprojectionSettings& reprojection) {
  std::vector<Buffer> shared = {Buffer::Color, Buffer::Albedo, Buffer::Normal, Buffer::Position, Buffer::Motion,
                                Buffer::Emission, Buffer::HiddenArea};
  if (reprojection.testDepth) {
    shared.push_back(Buffer::Depth);
    shared.push_back(Buffer::DepthGradient);
  }
  if (reprojection.testObjectId) shared.push_back(Buffer::ObjectId);
  std::vector<Buffer> used = required;
  auto add = [&](const std::vector<Buffer>& list) {
    for (Buffer b : list)
      if (std::find(used.begin(), used.end(), b) == used.end()) used.push_back(b);
  };
  add(shared);
  add(extra);
  return used;
}

bool streamsPastCache(size_t bytes) { return bytes >= (size_t(8) << 20); }

namespace {

// The sanitization of a value (core/sanitize.h): non-finite values become 0, finite ones are
// clamped into the buffer's range [lo, hi]; both counted. Magnitudes below kTiny become 0 (not
// counted: the hot loops never see a subnormal, core/flush.h). Non-finite and tiny values are
// recognized on the bits, so a subnormal input is never the operand of a floating-point
// instruction.
struct Bounds {
  float lo, hi;
  static constexpr uint32_t kMaxBits = std::bit_cast<uint32_t>(FLT_MAX), kTinyBits = std::bit_cast<uint32_t>(kTiny);
  /// The reference for sanitize8.
  float sanitize(float v, SanitizeCounts& bad) const {
    const uint32_t magnitude = std::bit_cast<uint32_t>(v) & 0x7fffffffu;
    if (magnitude > kMaxBits) {  // NaN and infinities
      ++bad.nonFinite;
      return 0.0f;
    }
    if (magnitude < kTinyBits) v = 0.0f;
    if (v < lo || v > hi) {
      ++bad.outOfRange;
      return v < lo ? lo : hi;
    }
    return v;
  }
};

#ifdef __AVX2__
inline __m256 sanitize8(__m256 v, Bounds b, SanitizeCounts& bad) {
  const __m256i magnitude = _mm256_and_si256(_mm256_castps_si256(v), _mm256_set1_epi32(0x7fffffff));
  const __m256i finite = _mm256_cmpgt_epi32(_mm256_set1_epi32(int(Bounds::kMaxBits) + 1), magnitude);
  const __m256i keep = _mm256_and_si256(finite, _mm256_cmpgt_epi32(magnitude, _mm256_set1_epi32(int(Bounds::kTinyBits) - 1)));
  v = _mm256_and_ps(v, _mm256_castsi256_ps(keep));  // non-finite and tiny values 0
  const __m256 clamped = _mm256_min_ps(_mm256_max_ps(v, _mm256_set1_ps(b.lo)), _mm256_set1_ps(b.hi));
  const unsigned ok = unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(finite)));
  const unsigned changed = unsigned(_mm256_movemask_ps(_mm256_cmp_ps(clamped, v, _CMP_NEQ_UQ)));
  bad.nonFinite += 8 - unsigned(__builtin_popcount(ok));
  bad.outOfRange += unsigned(__builtin_popcount(ok & changed));
  return clamped;
}

// The channels of eight pixels of `stride` (2, 3 or 4) floats each into out[0..stride).
// stride 3: v0 = r0 g0 b0 r1 g1 b1 r2 g2, v1 = b2 r3 ... r5, v2 = g5 b5 ... b7; channel c of
// pixel j is element 3j + c, so each channel is two blends (lanes from v0, v1, v2) and one
// lane permutation. stride 2 and 4: in-lane shuffles, then a cross-lane permutation.
inline void deinterleave8(const float* src, int stride, __m256 out[4]) {
  if (stride == 3) {
    const __m256 v0 = _mm256_loadu_ps(src), v1 = _mm256_loadu_ps(src + 8), v2 = _mm256_loadu_ps(src + 16);
    // lanes of v1 (first blend) and v2 (second blend) that hold channel c
    const __m256 r = _mm256_blend_ps(_mm256_blend_ps(v0, v1, 0b10010010), v2, 0b00100100);
    const __m256 g = _mm256_blend_ps(_mm256_blend_ps(v0, v1, 0b00100100), v2, 0b01001001);
    const __m256 b = _mm256_blend_ps(_mm256_blend_ps(v0, v1, 0b01001001), v2, 0b10010010);
    out[0] = _mm256_permutevar8x32_ps(r, _mm256_setr_epi32(0, 3, 6, 1, 4, 7, 2, 5));
    out[1] = _mm256_permutevar8x32_ps(g, _mm256_setr_epi32(1, 4, 7, 2, 5, 0, 3, 6));
    out[2] = _mm256_permutevar8x32_ps(b, _mm256_setr_epi32(2, 5, 0, 3, 6, 1, 4, 7));
  } else if (stride == 2) {
    const __m256 v0 = _mm256_loadu_ps(src), v1 = _mm256_loadu_ps(src + 8);
    // x0 x1 x4 x5 | x2 x3 x6 x7 -> x0 .. x7
    out[0] = _mm256_castpd_ps(_mm256_permute4x64_pd(_mm256_castps_pd(_mm256_shuffle_ps(v0, v1, 0x88)), 0xD8));
    out[1] = _mm256_castpd_ps(_mm256_permute4x64_pd(_mm256_castps_pd(_mm256_shuffle_ps(v0, v1, 0xDD)), 0xD8));
  } else {
    const __m256 v0 = _mm256_loadu_ps(src), v1 = _mm256_loadu_ps(src + 8), v2 = _mm256_loadu_ps(src + 16),
                 v3 = _mm256_loadu_ps(src + 24);
    const __m256 t0 = _mm256_unpacklo_ps(v0, v1), t1 = _mm256_unpackhi_ps(v0, v1);
    const __m256 t2 = _mm256_unpacklo_ps(v2, v3), t3 = _mm256_unpackhi_ps(v2, v3);
    // channel c of pixels 0 2 4 6 | 1 3 5 7
    const __m256i order = _mm256_setr_epi32(0, 4, 1, 5, 2, 6, 3, 7);
    out[0] = _mm256_permutevar8x32_ps(_mm256_shuffle_ps(t0, t2, 0x44), order);
    out[1] = _mm256_permutevar8x32_ps(_mm256_shuffle_ps(t0, t2, 0xEE), order);
    out[2] = _mm256_permutevar8x32_ps(_mm256_shuffle_ps(t1, t3, 0x44), order);
    out[3] = _mm256_permutevar8x32_ps(_mm256_shuffle_ps(t1, t3, 0xEE), order);
  }
}
#endif

// One row of tightly packed float pixels (`stride` floats each) into the nc planes' rows,
// sanitized (counted in `bad`). All channels in one pass over the row.
// `stream`: write around the caches (non-temporal stores, where the rows are 32-byte aligned),
// for frames too large to stay in cache until the next pass reads them: it saves reading
// each destination line before overwriting it (measured on the CI-class VM at 1280x720,
// 2 threads: import 4.1 -> 3.0 ms).
void importFloatRow(const float* src, int stride, int nc, float* const* dst, int w, Bounds b, bool stream,
                    SanitizeCounts& bad) {
  int x = 0;
#ifdef __AVX2__
  for (int c = 0; c < nc; ++c) stream = stream && reinterpret_cast<uintptr_t>(dst[c]) % 32 == 0;
  auto store = [&](float* p, __m256 v) {
    if (stream) _mm256_stream_ps(p, v);
    else _mm256_storeu_ps(p, v);
  };
  if (stride >= 2 && stride <= 4) {
    for (; x + 8 <= w; x += 8) {
      __m256 v[4];
      deinterleave8(src + size_t(x) * stride, stride, v);
      for (int c = 0; c < nc; ++c) store(dst[c] + x, sanitize8(v[c], b, bad));
    }
  } else if (stride == 1) {
    for (; x + 8 <= w; x += 8) store(dst[0] + x, sanitize8(_mm256_loadu_ps(src + x), b, bad));
  }
  if (stream) _mm_sfence();  // the streamed stores are weakly ordered: complete them before the row is handed on
#endif
  for (; x < w; ++x)
    for (int c = 0; c < nc; ++c) dst[c][x] = b.sanitize(src[size_t(x) * stride + c], bad);
}

}  // namespace

uint64_t importFrame(const FrameInputs& in, const std::vector<Buffer>& required, FrameData& out,
                     const std::vector<Buffer>* used, SanitizeStats* counts) {
  checkInputViews(in, required);
  const ImageView& color = in[Buffer::Color];
  const int w = color.width, h = color.height;

  out.width = w;
  out.height = h;
  out.camera = in.camera;
  SanitizeStats stats{};
  auto wanted = [&](int i) {
    return !in.buffers[i].empty() && (!used || std::find(used->begin(), used->end(), Buffer(i)) != used->end());
  };
  size_t importedBytes = 0;
  for (int i = 0; i < kBufferCount; ++i)
    if (wanted(i)) importedBytes += size_t(w) * h * sizeof(float) * bufferChannelCount(Buffer(i));
  const bool stream = streamsPastCache(importedBytes);
  for (int i = 0; i < kBufferCount; ++i) {
    const ImageView& v = in.buffers[i];
    auto& planes = out.buffers[i];
    if (!wanted(i)) {
      planes.clear();
      continue;
    }
    const Buffer b = Buffer(i);
    const int nc = bufferChannelCount(b);
    planes.resize(nc);
    for (auto& p : planes)
      if (p.width != w || p.height != h) p.resize(w, h);
    const bool ints = v.format == Format::Int32;
    const size_t pixelFloats = v.bytesPerPixel() / 4, rowStride = v.bytesPerRow();  // multiples of 4 (checked)
    const ValueRange range = importRange(b);
    const Bounds bounds{range.lo, range.hi};
    std::atomic<uint64_t> nonFinite{0}, outOfRange{0};
    parallelRows(h, [&](int y) {
      const char* src = static_cast<const char*>(v.data) + size_t(y) * rowStride;
      float* dst[4];
      for (int c = 0; c < nc; ++c) dst[c] = planes[c].row(y);
      SanitizeCounts bad;
      if (!ints) {
        importFloatRow(reinterpret_cast<const float*>(src), int(pixelFloats), nc, dst, w, bounds, stream, bad);
      } else {
        const int32_t* ids = reinterpret_cast<const int32_t*>(src);
        for (int x = 0; x < w; ++x)
          for (int c = 0; c < nc; ++c) dst[c][x] = bounds.sanitize(float(ids[size_t(x) * pixelFloats + c]), bad);
      }
      if (bad.nonFinite) nonFinite += bad.nonFinite;
      if (bad.outOfRange) outOfRange += bad.outOfRange;
    }, 16);
    stats[size_t(i)].nonFinite = nonFinite;
    stats[size_t(i)].outOfRange = outOfRange;
  }
  sanitizeUnitVectors(out, stats);
  separateEmission(out);
  applyHiddenArea(out);
  uint64_t total = 0;
  for (const SanitizeCounts& c : stats) total += c.total();
  if (counts) *counts = stats;
  return total;
}

void applyHiddenArea(FrameData& f) {
  if (!f.has(Buffer::HiddenArea)) return;
  const Plane& hidden = f.plane(Buffer::HiddenArea);
  for (int i = 0; i < kBufferCount; ++i) {
    const Buffer b = Buffer(i);
    if (!f.has(b) || !(isRadianceBuffer(b) || b == Buffer::Normal)) continue;
    parallelRows(f.height, [&](int y) {
      const float* m = hidden.row(y);
      for (auto& plane : f.buffers[i]) {
        float* v = plane.row(y);
        for (int x = 0; x < f.width; ++x)
          if (m[x] > 0.5f) v[x] = 0.0f;
      }
    });
  }
}

void separateEmission(FrameData& f) {
  if (!f.has(Buffer::Emission)) return;
  // The renderer counts primary-hit emission in Color, Direct and Diffuse.
  for (Buffer b : {Buffer::Color, Buffer::Direct, Buffer::Diffuse}) {
    if (!f.has(b)) continue;
    parallelRows(f.height, [&](int y) {
      for (int c = 0; c < 3; ++c) {
        float* v = f.plane(b, c).row(y);
        const float* e = f.plane(Buffer::Emission, c).row(y);
        for (int x = 0; x < f.width; ++x) v[x] = std::max(0.0f, v[x] - e[x]);
      }
    });
  }
}

namespace {
#ifdef __AVX2__
// The inverse of deinterleave8: eight pixels of channels c[0..stride) into `stride` (3 or 4)
// vectors of packed pixels. stride 3: each channel is permuted so that its values sit in the
// lanes they take in the three output vectors, then two blends per vector assemble them.
inline void interleave8(const __m256 c[4], int stride, __m256 out[4]) {
  if (stride == 3) {
    const __m256 r = _mm256_permutevar8x32_ps(c[0], _mm256_setr_epi32(0, 3, 6, 1, 4, 7, 2, 5));
    const __m256 g = _mm256_permutevar8x32_ps(c[1], _mm256_setr_epi32(5, 0, 3, 6, 1, 4, 7, 2));
    const __m256 b = _mm256_permutevar8x32_ps(c[2], _mm256_setr_epi32(2, 5, 0, 3, 6, 1, 4, 7));
    out[0] = _mm256_blend_ps(_mm256_blend_ps(r, g, 0b10010010), b, 0b00100100);
    out[1] = _mm256_blend_ps(_mm256_blend_ps(r, g, 0b00100100), b, 0b01001001);
    out[2] = _mm256_blend_ps(_mm256_blend_ps(r, g, 0b01001001), b, 0b10010010);
  } else {
    const __m256 t0 = _mm256_unpacklo_ps(c[0], c[1]), t1 = _mm256_unpackhi_ps(c[0], c[1]);
    const __m256 t2 = _mm256_unpacklo_ps(c[2], c[3]), t3 = _mm256_unpackhi_ps(c[2], c[3]);
    // pixels 0|4, 1|5, 2|6, 3|7
    const __m256 p04 = _mm256_shuffle_ps(t0, t2, 0x44), p15 = _mm256_shuffle_ps(t0, t2, 0xEE);
    const __m256 p26 = _mm256_shuffle_ps(t1, t3, 0x44), p37 = _mm256_shuffle_ps(t1, t3, 0xEE);
    out[0] = _mm256_permute2f128_ps(p04, p15, 0x20);
    out[1] = _mm256_permute2f128_ps(p26, p37, 0x20);
    out[2] = _mm256_permute2f128_ps(p04, p15, 0x31);
    out[3] = _mm256_permute2f128_ps(p26, p37, 0x31);
  }
}
#endif
}  // namespace

void exportRgb(const Plane3& rgb, const std::vector<Plane>* emission, const ImageView& out) {
  if (out.format != Format::Float3 && out.format != Format::Float4)
    throw Error("output view must be Float3 or Float4");
  if (out.width != rgb[0].width || out.height != rgb[0].height)
    throw Error("output view is " + std::to_string(out.width) + "x" + std::to_string(out.height) +
                ", the frame is " + std::to_string(rgb[0].width) + "x" + std::to_string(rgb[0].height));
  const bool alpha = out.format == Format::Float4;
  const int stride = alpha ? 4 : 3;
  const bool packed = out.bytesPerPixel() == size_t(stride) * sizeof(float);
  const bool stream = streamsPastCache(size_t(out.width) * out.height * out.bytesPerPixel());
  parallelRows(out.height, [&](int y) {
    const float* c[3] = {rgb[0].row(y), rgb[1].row(y), rgb[2].row(y)};
    const float* e[3] = {nullptr, nullptr, nullptr};
    if (emission)
      for (int k = 0; k < 3; ++k) e[k] = (*emission)[k].row(y);
    int x = 0;
#ifdef __AVX2__
    if (packed) {
      float* row = out.pixel<float>(0, y);
      const bool nonTemporal = stream && reinterpret_cast<uintptr_t>(row) % 32 == 0;
      for (; x + 8 <= out.width; x += 8) {
        __m256 v[4], p[4];
        for (int k = 0; k < 3; ++k) {
          v[k] = _mm256_loadu_ps(c[k] + x);
          if (emission) v[k] = _mm256_add_ps(v[k], _mm256_loadu_ps(e[k] + x));
        }
        v[3] = _mm256_set1_ps(1.0f);
        interleave8(v, stride, p);
        for (int k = 0; k < stride; ++k) {
          float* dst = row + size_t(x) * stride + 8 * k;
          if (nonTemporal) _mm256_stream_ps(dst, p[k]);
          else _mm256_storeu_ps(dst, p[k]);
        }
      }
      if (nonTemporal) _mm_sfence();
    }
#endif
    for (; x < out.width; ++x) {
      float* p = out.pixel<float>(x, y);
      for (int k = 0; k < 3; ++k) p[k] = emission ? c[k][x] + e[k][x] : c[k][x];
      if (alpha) p[3] = 1.0f;
    }
  });
}

}  // namespace rtd
