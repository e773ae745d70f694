// rtdenoise — images: a non-owning strided view (what the API takes) and an owning float image.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace rtd {

/// Largest image the library accepts, in views and in files: each side at most kMaxImageSide
/// pixels and at most kMaxImagePixels pixels in all (8192 x 8192, or 16384 x 4096). A view or
/// a file header claiming more is refused with rtd::Error before anything is allocated.
constexpr int kMaxImageSide = 16384;
constexpr int64_t kMaxImagePixels = int64_t(1) << 26;

/// Pixel formats a view may have. Floats are 32-bit IEEE; Int32 is for ids; Half* are 16-bit
/// IEEE half floats (binary16), as engines keep G-buffers and as the Vulkan backend also reads
/// from R16*_SFLOAT images. Outputs are Float3/Float4 or Half3/Half4.
enum class Format : uint8_t { Undefined, Float, Float2, Float3, Float4, Int32, Half, Half2, Half3, Half4 };

/// Number of scalar channels of a format (0 for Undefined).
constexpr int channelCount(Format f) {
  switch (f) {
    case Format::Float: case Format::Int32: case Format::Half: return 1;
    case Format::Float2: case Format::Half2: return 2;
    case Format::Float3: case Format::Half3: return 3;
    case Format::Float4: case Format::Half4: return 4;
    default: return 0;
  }
}
/// True for the 16-bit half-float formats.
constexpr bool isHalf(Format f) {
  return f == Format::Half || f == Format::Half2 || f == Format::Half3 || f == Format::Half4;
}
/// Bytes of one channel: 2 for Half*, 4 otherwise.
constexpr int channelBytes(Format f) { return isHalf(f) ? 2 : 4; }

/// A strided view of pixels owned by the caller, as in Open Image Denoise's shared buffers.
/// `pixelStride` and `rowStride` are in bytes; 0 means tightly packed (channelBytes() per
/// channel). Both backends check every view the same way before touching history: `data`
/// aligned to the channel size (4 bytes, 2 for Half*), strides multiples of it, `pixelStride`
/// at least the format's size and `rowStride` at least width * pixelStride, the size positive
/// and within kMaxImageSide / kMaxImagePixels.
/// Rows run from the top of the image (row 0 is the top), x to the right.
struct ImageView {
  void* data = nullptr;
  int width = 0;
  int height = 0;
  Format format = Format::Undefined;
  size_t pixelStride = 0;
  size_t rowStride = 0;

  bool empty() const { return data == nullptr; }
  int channels() const { return channelCount(format); }
  size_t bytesPerPixel() const { return pixelStride ? pixelStride : size_t(channels()) * channelBytes(format); }
  size_t bytesPerRow() const { return rowStride ? rowStride : bytesPerPixel() * size_t(width); }
  /// Address of pixel (x, y); channel c is at `pixel(x, y) + c` (T = uint16_t for Half*).
  template <class T = float> T* pixel(int x, int y) const {
    return reinterpret_cast<T*>(static_cast<char*>(data) + size_t(y) * bytesPerRow() +
                                size_t(x) * bytesPerPixel());
  }
};

/// An owning image of `channels` interleaved floats per pixel, rows from the top.
struct Image {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<float> pixels;

  Image() = default;
  Image(int w, int h, int c, float fill = 0.0f)
      : width(w), height(h), channels(c), pixels(size_t(w) * h * c, fill) {}

  float* pixel(int x, int y) { return pixels.data() + (size_t(y) * width + x) * channels; }
  const float* pixel(int x, int y) const { return pixels.data() + (size_t(y) * width + x) * channels; }
  float& at(int x, int y, int c = 0) { return pixel(x, y)[c]; }
  float at(int x, int y, int c = 0) const { return pixel(x, y)[c]; }
  bool empty() const { return pixels.empty(); }

  /// A view of this image; only 1 to 4 channels have a Format.
  ImageView view() {
    static constexpr Format kFormats[] = {Format::Undefined, Format::Float, Format::Float2,
                                          Format::Float3, Format::Float4};
    return ImageView{pixels.data(), width, height, channels <= 4 ? kFormats[channels] : Format::Undefined,
                     0, 0};
  }
  ImageView view() const { return const_cast<Image*>(this)->view(); }
};

}  // namespace rtd
