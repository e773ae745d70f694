#include "core/frame_data.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>

#include "core/parallel.h"
#include "rtd/error.h"

namespace rtd {

bool isRadianceBuffer(Buffer b) {
  switch (b) {
    case Buffer::Color: case Buffer::Direct: case Buffer::Indirect:
    case Buffer::Diffuse: case Buffer::Specular: case Buffer::Emission: return true;
    default: return false;
  }
}

static std::string describe(Buffer b) { return "buffer '" + std::string(bufferName(b)) + "'"; }

std::vector<Buffer> importedBuffers(const std::vector<Buffer>& required, const std::vector<Buffer>& extra,
                                    const ReprojectionSettings& reprojection) {
  std::vector<Buffer> shared = {Buffer::Color, Buffer::Albedo, Buffer::Normal, Buffer::Position, Buffer::Motion,
                                Buffer::Emission};
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

namespace {
template <int kStride> void deinterleave(const float* __restrict src, float* __restrict dst, int w) {
  for (int x = 0; x < w; ++x) dst[x] = src[x * kStride];
}
}  // namespace

uint64_t importFrame(const FrameInputs& in, const std::vector<Buffer>& required, FrameData& out,
                     const std::vector<Buffer>* used) {
  for (Buffer b : required)
    if (!in.has(b)) throw Error("missing required " + describe(b));
  const ImageView& color = in[Buffer::Color];
  const int w = color.width, h = color.height;
  if (w <= 0 || h <= 0) throw Error("buffer 'color' has an empty size");
  for (int i = 0; i < kBufferCount; ++i) {
    const ImageView& v = in.buffers[i];
    if (v.empty()) continue;
    Buffer b = Buffer(i);
    if (v.width != w || v.height != h)
      throw Error(describe(b) + " is " + std::to_string(v.width) + "x" + std::to_string(v.height) +
                  " but color is " + std::to_string(w) + "x" + std::to_string(h));
    if (v.channels() < bufferChannelCount(b))
      throw Error(describe(b) + " needs " + std::to_string(bufferChannelCount(b)) + " channels, the view has " +
                  std::to_string(v.channels()));
  }

  out.width = w;
  out.height = h;
  out.camera = in.camera;
  std::atomic<uint64_t> replaced{0};
  for (int i = 0; i < kBufferCount; ++i) {
    const ImageView& v = in.buffers[i];
    const bool wanted = !used || std::find(used->begin(), used->end(), Buffer(i)) != used->end();
    auto& planes = out.buffers[i];
    if (v.empty() || !wanted) {
      planes.clear();
      continue;
    }
    const Buffer b = Buffer(i);
    const int nc = bufferChannelCount(b);
    planes.resize(nc);
    for (auto& p : planes)
      if (p.width != w || p.height != h) p.resize(w, h);
    const bool radiance = isRadianceBuffer(b);
    const bool ints = v.format == Format::Int32;
    const size_t pixelStride = v.bytesPerPixel(), rowStride = v.bytesPerRow();
    parallelRows(h, [&](int y) {
      const char* src = static_cast<const char*>(v.data) + size_t(y) * rowStride;
      uint64_t bad = 0;
      for (int c = 0; c < nc; ++c) {
        float* dst = planes[c].row(y);
        // De-interleave one channel of the row (strided loads, contiguous stores); tightly
        // packed float pixels of 1-4 channels take a loop with a constant stride, which GCC
        // vectorizes with shuffles.
        if (ints) {
          for (int x = 0; x < w; ++x) dst[x] = float(*reinterpret_cast<const int32_t*>(src + x * pixelStride + c * 4));
        } else {
          const float* s = reinterpret_cast<const float*>(src) + c;
          switch (pixelStride) {
            case 4: std::copy(s, s + w, dst); break;
            case 8: deinterleave<2>(s, dst, w); break;
            case 12: deinterleave<3>(s, dst, w); break;
            case 16: deinterleave<4>(s, dst, w); break;
            default:
              for (int x = 0; x < w; ++x) dst[x] = *reinterpret_cast<const float*>(src + x * pixelStride + c * 4);
          }
        }
        // Radiance must be finite and non-negative before it can reach history (a NaN would
        // stay in the exponential average for ever); features only need to be finite.
        // Branch-free so the loop vectorizes; the comparisons are false for NaN.
        if (radiance) {
          for (int x = 0; x < w; ++x) {
            const bool ok = dst[x] >= 0.0f && dst[x] <= 3.0e38f;
            bad += !ok;
            dst[x] = ok ? dst[x] : 0.0f;
          }
        } else {
          for (int x = 0; x < w; ++x) {
            const bool ok = dst[x] >= -3.0e38f && dst[x] <= 3.0e38f;
            bad += !ok;
            dst[x] = ok ? dst[x] : 0.0f;
          }
        }
      }
      if (bad) replaced += bad;
    }, 16);
  }
  separateEmission(out);
  return replaced;
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

void exportRgb(const Plane3& rgb, const std::vector<Plane>* emission, const ImageView& out) {
  if (out.format != Format::Float3 && out.format != Format::Float4)
    throw Error("output view must be Float3 or Float4");
  if (out.width != rgb[0].width || out.height != rgb[0].height)
    throw Error("output view is " + std::to_string(out.width) + "x" + std::to_string(out.height) +
                ", the frame is " + std::to_string(rgb[0].width) + "x" + std::to_string(rgb[0].height));
  const bool alpha = out.format == Format::Float4;
  parallelRows(out.height, [&](int y) {
    const float *r = rgb[0].row(y), *g = rgb[1].row(y), *b = rgb[2].row(y);
    for (int x = 0; x < out.width; ++x) {
      float* p = out.pixel<float>(x, y);
      p[0] = r[x]; p[1] = g[x]; p[2] = b[x];
      if (emission) {
        p[0] += (*emission)[0].row(y)[x];
        p[1] += (*emission)[1].row(y)[x];
        p[2] += (*emission)[2].row(y)[x];
      }
      if (alpha) p[3] = 1.0f;
    }
  });
}

}  // namespace rtd
