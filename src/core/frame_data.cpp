#include "core/frame_data.h"

#include <algorithm>
#include <bit>
#include <atomic>
#include <cfloat>
#include <cmath>
#include <string>

#include "core/frame_data_kernels.h"
#include "core/half.h"
#include "core/parallel.h"
#include "core/sanitize.h"
#include "core/validate.h"
#include "rtd/error.h"

namespace rtd {

bool isRadianceBuffer(Buffer b) {
  switch (b) {
    case Buffer::Color: case Buffer::Direct: case Buffer::Indirect:
    case Buffer::Diffuse: case Buffer::Specular: case Buffer::Emission: case Buffer::IndirectDiffuse: return true;
    default: return false;
  }
}

std::vector<Buffer> importedBuffers(const std::vector<Buffer>& required, const std::vector<Buffer>& extra,
                                    const ReprojectionSettings& reprojection, bool frameHasMotion) {
  std::vector<Buffer> shared = {Buffer::Color, Buffer::Albedo, Buffer::Normal, Buffer::Motion, Buffer::Emission,
                                Buffer::HiddenArea};
  // World positions: for the reprojection's position test, and in place of motion vectors (the
  // previous camera projects them). Otherwise 12 bytes a pixel not to copy (~1 ms of svgf's
  // import at 1280x720).
  if (reprojection.testsPosition() || !frameHasMotion) shared.push_back(Buffer::Position);
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
  // Emission first: Color, Direct and Diffuse subtract it on their way in.
  const bool emission = wanted(int(Buffer::Emission));
  auto subtractsEmission = [&](Buffer b) {
    return emission && (b == Buffer::Color || b == Buffer::Direct || b == Buffer::Diffuse);
  };
  std::vector<int> order{int(Buffer::Emission)};
  for (int i = 0; i < kBufferCount; ++i)
    if (i != int(Buffer::Emission)) order.push_back(i);
  for (int i : order) {
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
    const bool half = isHalf(v.format);
    const size_t pixelStride = v.bytesPerPixel(), rowStride = v.bytesPerRow();  // multiples of the channel size (checked)
    const size_t pixelFloats = pixelStride / 4;
    const ValueRange range = importRange(b);
    const Bounds bounds{range.lo, range.hi};
    const bool unitVectors = isUnitVectorBuffer(b), minusEmission = subtractsEmission(b);
    std::atomic<uint64_t> nonFinite{0}, outOfRange{0}, renormalized{0};
    parallelRows(h, [&](int y) {
      const char* src = static_cast<const char*>(v.data) + size_t(y) * rowStride;
      float* dst[4];
      for (int c = 0; c < nc; ++c) dst[c] = planes[c].row(y);
      const float* e[3] = {nullptr, nullptr, nullptr};
      if (minusEmission)
        for (int c = 0; c < 3; ++c) e[c] = out.plane(Buffer::Emission, c).row(y);
      SanitizeCounts bad;
      bool check = unitVectors;  // whether the row may hold a vector to renormalize
      bool subtract = minusEmission;  // emission still to subtract
      if (half) {
        importHalfRow(src, pixelStride, nc, dst, w, range, bad);
      } else if (!ints) {
        RowFixes fixes;
        fixes.emission = minusEmission ? e : nullptr;
        fixes.unitVectors = unitVectors;
        check = RTD_SIMD(importFloatRow)(reinterpret_cast<const float*>(src), int(pixelFloats), nc, dst, w, bounds,
                                         stream, fixes, bad);
        subtract = false;
      } else {
        const int32_t* ids = reinterpret_cast<const int32_t*>(src);
        for (int x = 0; x < w; ++x)
          for (int c = 0; c < nc; ++c) dst[c][x] = bounds.sanitize(float(ids[size_t(x) * pixelFloats + c]), bad);
      }
      if (subtract) subtractEmissionRow(dst, e, w);
      if (check) {
        const uint64_t n = renormalizeRow(dst[0], dst[1], dst[2], w);
        if (n) renormalized += n;
      }
      if (bad.nonFinite) nonFinite += bad.nonFinite;
      if (bad.outOfRange) outOfRange += bad.outOfRange;
    }, 16);
    stats[size_t(i)].nonFinite = nonFinite;
    stats[size_t(i)].outOfRange = outOfRange;
    stats[size_t(i)].renormalized = renormalized;
  }
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

void subtractEmissionRow(float* const* v, const float* const* e, int w) {
  for (int c = 0; c < 3; ++c)
    for (int x = 0; x < w; ++x) v[c][x] = std::max(0.0f, flushTiny(v[c][x] - e[c][x]));
}

RgbExport::RgbExport(const ImageView& out, int width, int height, const std::vector<Plane>* emission)
    : out_(out), emission_(emission), half_(isHalf(out.format)) {
  if (out.format != Format::Float3 && out.format != Format::Float4 && !half_)
    throw Error("output view must be Float3, Float4, Half3 or Half4");
  if (out.width != width || out.height != height)
    throw Error("output view is " + std::to_string(out.width) + "x" + std::to_string(out.height) +
                ", the frame is " + std::to_string(width) + "x" + std::to_string(height));
  const size_t channelBytes = half_ ? 2 : sizeof(float);
  packed_ = out.bytesPerPixel() == size_t(channelCount(out.format)) * channelBytes;
  stream_ = !half_ && streamsPastCache(size_t(out.width) * out.height * out.bytesPerPixel());
}

void RgbExport::row(int y, const float* const rgb[3]) const {
  const float* e[3] = {nullptr, nullptr, nullptr};
  if (emission_)
    for (int k = 0; k < 3; ++k) e[k] = (*emission_)[k].row(y);
  if (half_) exportHalfRow(rgb, emission_ ? e : nullptr, out_, y, packed_);
  else RTD_SIMD(exportRow)(rgb, emission_ ? e : nullptr, out_, y, packed_, stream_);
}

void exportRgb(const Plane3& rgb, const std::vector<Plane>* emission, const ImageView& out) {
  const RgbExport rows(out, rgb[0].width, rgb[0].height, emission);
  parallelRows(out.height, [&](int y) {
    const float* c[3] = {rgb[0].row(y), rgb[1].row(y), rgb[2].row(y)};
    rows.row(y, c);
  });
}

}  // namespace rtd
