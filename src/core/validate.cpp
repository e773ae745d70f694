#include "core/validate.h"

#include <cmath>
#include <cstdint>

#include "rtd/error.h"

namespace rtd {

namespace {

std::string describe(Buffer b) { return "buffer '" + std::string(bufferName(b)) + "'"; }
std::string sizeText(long long w, long long h) { return std::to_string(w) + "x" + std::to_string(h); }

// Pointer alignment and strides of a host view.
void checkLayout(const std::string& what, const ImageView& v) {
  const size_t unit = size_t(channelBytes(v.format));
  if (reinterpret_cast<uintptr_t>(v.data) % unit)
    throw Error(what + ": data pointer is not " + std::to_string(unit) + "-byte aligned (pixels are " +
                std::to_string(8 * unit) + "-bit values)");
  checkStrides(what, v.format, v.pixelStride, v.rowStride, v.width);
}

void checkMatrix(const std::array<float, 16>& m, const char* name) {
  for (int i = 0; i < 16; ++i)
    if (!std::isfinite(m[size_t(i)]))
      throw Error(std::string("camera: ") + name + "[" + std::to_string(i) + "] is not finite");
}

}  // namespace

void checkImageSize(const std::string& what, long long width, long long height) {
  if (width <= 0 || height <= 0) throw Error(what + " has an empty size (" + sizeText(width, height) + ")");
  if (width > kMaxImageSide || height > kMaxImageSide || width * height > kMaxImagePixels)
    throw Error(what + " is " + sizeText(width, height) + ", larger than the largest image rtdenoise accepts (" +
                std::to_string(kMaxImageSide) + " pixels a side, " + std::to_string(kMaxImagePixels) + " pixels)");
}

void checkStrides(const std::string& what, Format format, size_t pixelStride, size_t rowStride, int width) {
  const size_t unit = size_t(channelBytes(format)), packed = size_t(channelCount(format)) * unit;
  if (pixelStride % unit || rowStride % unit)
    throw Error(what + ": pixel stride " + std::to_string(pixelStride) + " and row stride " + std::to_string(rowStride) +
                " must be multiples of " + std::to_string(unit) + " bytes");
  if (pixelStride && pixelStride < packed)
    throw Error(what + ": pixel stride " + std::to_string(pixelStride) + " is smaller than a pixel of the format (" +
                std::to_string(packed) + " bytes)");
  const size_t pixel = pixelStride ? pixelStride : packed;
  if (rowStride && rowStride < pixel * size_t(width))
    throw Error(what + ": row stride " + std::to_string(rowStride) + " is smaller than a row (" +
                std::to_string(width) + " pixels of " + std::to_string(pixel) + " bytes)");
}

void checkInputViews(const FrameInputs& in, const std::vector<Buffer>& required) {
  for (Buffer b : required)
    if (!in.has(b)) throw Error("missing required " + describe(b));
  if (!in.has(Buffer::Color)) throw Error("missing required " + describe(Buffer::Color));
  const ImageView& color = in[Buffer::Color];
  const int w = color.width, h = color.height;
  checkImageSize(describe(Buffer::Color), w, h);
  for (int i = 0; i < kBufferCount; ++i) {
    const ImageView& v = in.buffers[size_t(i)];
    if (v.empty()) continue;
    const Buffer b = Buffer(i);
    if (v.width != w || v.height != h)
      throw Error(describe(b) + " is " + sizeText(v.width, v.height) + " but color is " + sizeText(w, h));
    if (v.format == Format::Undefined || v.channels() == 0)
      throw Error(describe(b) + " has no format (Format::Undefined or an unknown value)");
    if (v.channels() < bufferChannelCount(b))
      throw Error(describe(b) + " needs " + std::to_string(bufferChannelCount(b)) + " channels, the view has " +
                  std::to_string(v.channels()));
    checkLayout(describe(b), v);
  }
  checkCamera(in.camera);
}

void checkCamera(const Camera& camera) {
  if (!camera.valid) return;
  checkMatrix(camera.worldToCamera, "worldToCamera");
  checkMatrix(camera.projection, "projection");
}

void checkOutputView(const ImageView& out, int width, int height) {
  if (out.empty()) throw Error("output view is empty");
  if (out.format != Format::Float3 && out.format != Format::Float4 && out.format != Format::Half3 &&
      out.format != Format::Half4)
    throw Error("output view must be Float3, Float4, Half3 or Half4");
  if (out.width != width || out.height != height)
    throw Error("output view is " + sizeText(out.width, out.height) + ", the frame (buffer 'color') is " +
                sizeText(width, height));
  checkLayout("output view", out);
}

}  // namespace rtd
