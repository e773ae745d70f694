// What both backends check of a frame before any history is touched: every image view's
// format, memory layout and size, the camera, and the output view. One implementation, so the
// CPU and Vulkan denoisers accept and refuse exactly the same inputs with the same messages.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "rtd/frame.h"

namespace rtd {

/// Throws rtd::Error unless width x height is a positive size within kMaxImageSide and
/// kMaxImagePixels; `what` starts the message ("buffer 'color'", "file 'a.exr'").
void checkImageSize(const std::string& what, long long width, long long height);

/// Throws rtd::Error unless a layout of pixels of `format` (32-bit values, 16-bit for Half*)
/// with these strides (bytes; 0 = tightly packed) is well formed for rows of `width` pixels:
/// strides multiples of the channel size, the pixel stride at least a pixel of the format, the
/// row stride at least width * pixel stride.
void checkStrides(const std::string& what, Format format, size_t pixelStride, size_t rowStride, int width);

/// Every non-empty view of `in`: the colour view's size (checkImageSize), each view's size
/// equal to colour's, its format with enough channels for its buffer, a pointer aligned to
/// the channel size (4 bytes, 2 for Half*) and well-formed strides; every buffer in `required` present; the camera's matrices
/// finite where it is valid. Throws rtd::Error naming the buffer and what is wrong.
void checkInputViews(const FrameInputs& in, const std::vector<Buffer>& required);

/// Where `camera.valid`: every matrix entry finite (rtd::Error naming the entry otherwise).
void checkCamera(const Camera& camera);

/// The output view of a frame of width x height: non-empty, Float3, Float4, Half3 or Half4, that
/// size, aligned, well-formed strides.
void checkOutputView(const ImageView& out, int width, int height);

}  // namespace rtd
