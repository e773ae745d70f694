// rtdenoise — frame sequences on disk: the native format (docs/sequence-format.md) and
// Blender Cycles multilayer EXR sequences, plus writing denoised frames.
#pragma once
#include <array>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "rtd/frame.h"
#include "rtd/image.h"

namespace rtd {

/// One frame in memory: an image per buffer present (channels as bufferChannels()).
struct Frame {
  int number = 0;  ///< frame number as in the file name (frame_0007.exr -> 7)
  int width = 0, height = 0;
  std::array<Image, kBufferCount> buffers;
  Camera camera;

  bool has(Buffer b) const { return !buffers[int(b)].empty(); }
  Image& operator[](Buffer b) { return buffers[int(b)]; }
  const Image& operator[](Buffer b) const { return buffers[int(b)]; }
  /// Views of every buffer present, for Denoiser::denoise().
  FrameInputs inputs() const;
};

enum class SequenceKind { Native, Blender };

/// Reads a sequence directory frame by frame. open() detects the kind: a directory with
/// sequence.json is native; one with multilayer EXR files holding a `<layer>.Combined.R`
/// channel is a Blender Cycles sequence. Errors (rtd::Error) name the file, frame and channel.
class SequenceReader {
 public:
  static std::unique_ptr<SequenceReader> open(const std::filesystem::path& dir);
  virtual ~SequenceReader() = default;
  virtual SequenceKind kind() const = 0;
  virtual int frameCount() const = 0;
  virtual int frameNumber(int index) const = 0;
  virtual std::filesystem::path framePath(int index) const = 0;
  /// Image size (of the first frame; every frame must match).
  virtual int width() const = 0;
  virtual int height() const = 0;
  /// Buffers every frame of this sequence holds.
  virtual std::vector<Buffer> buffers() const = 0;
  virtual Frame read(int index) const = 0;
};

/// Writes a native sequence: frame EXRs and sequence.json. Each file is written to a temporary
/// name and renamed, so an interrupted run never leaves a truncated file.
class SequenceWriter {
 public:
  explicit SequenceWriter(std::filesystem::path dir);
  /// Writes frame_NNNN.exr with every buffer the frame has; remembers its camera.
  void write(const Frame& frame);
  /// Writes sequence.json describing the frames written so far (call after the last frame,
  /// or after each frame to keep a partial sequence readable).
  void finish() const;
  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
  std::vector<std::pair<int, Camera>> frames_;
  int width_ = 0, height_ = 0;
  std::vector<Buffer> buffers_;
};

/// Pixel type of written EXR channels.
enum class ExrPixels { Float, Half };

/// Writes an RGB image as an EXR with channels R, G, B (linear), atomically: 32-bit float, or
/// 16-bit half (values beyond 65504 become infinite, as OpenEXR converts them).
void writeRgbExr(const std::filesystem::path& path, const Image& rgb, ExrPixels pixels = ExrPixels::Float);
/// Reads the R, G, B channels of an EXR (single-part, top-level channels).
Image readRgbExr(const std::filesystem::path& path);

/// Writes `data` to `path` atomically (temporary file in the same directory, then rename).
void writeFileAtomic(const std::filesystem::path& path, const std::string& data);

}  // namespace rtd
