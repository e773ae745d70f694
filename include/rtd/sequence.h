// rtdenoise — frame sequences on disk: the native format (docs/sequence-format.md) and
// per-buffer image files and Blender Cycles multilayer EXR sequences, plus writing denoised frames.
#pragma once
#include <array>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "rtd/frame.h"
#include "rtd/image.h"

namespace rtd {

struct GuideRaySamples;  // include/rtd/guide_rays.h

/// One frame in memory: an image per buffer present (channels as bufferChannels()).
struct Frame {
  int number = 0;  ///< frame number as in the file name (frame_0007.exr -> 7)
  int width = 0, height = 0;
  std::array<Image, kBufferCount> buffers;
  Camera camera;
  /// History is invalid at this frame: a camera cut marked by the sequence or the caller, or a
  /// gap in the frame numbering (SequenceReader). inputs() passes it as FrameInputs::cameraCut.
  bool cut = false;

  bool has(Buffer b) const { return !buffers[int(b)].empty(); }
  Image& operator[](Buffer b) { return buffers[int(b)]; }
  const Image& operator[](Buffer b) const { return buffers[int(b)]; }
  /// Views of every buffer present, for Denoiser::denoise().
  FrameInputs inputs() const;
};

enum class SequenceKind { Native, PerBuffer, Blender };
/// "native", "per-buffer" or "blender".
std::string_view sequenceKindName(SequenceKind kind);

/// Frame numbers lie in [0, kMaxFrameNumber] (a sequence claiming others is refused).
constexpr int kMaxFrameNumber = 2147483647;

/// What a reader is told beyond what the files say (the CLI's --cut and --continuous).
struct SequenceOptions {
  /// Frame numbers at which history is reset (camera cuts), besides those the sequence marks.
  std::vector<int> cuts;
  /// Gaps in the frame numbering are not cuts (e.g. every other frame was rendered). By
  /// default a frame whose number is not the previous one's + 1 resets history, because its
  /// motion vectors point to a frame that is not there.
  bool continuous = false;
};

/// Reads a sequence directory frame by frame. open() detects the kind: a directory with
/// sequence.json is native; one with per-buffer files `<buffer>_<number>.<ext>` (color_0001.exr,
/// albedo_0001.pfm, ...; EXR, PFM, HDR, PNG or TIFF, the latter through OpenImageIO) is
/// per-buffer, with cameras from an optional cameras.json; one with multilayer EXR files
/// holding a `<layer>.Combined.R` channel is a Blender Cycles sequence. Frame numbers are unique, sorted and within
/// [0, kMaxFrameNumber]. Files are untrusted: headers are checked against limits and the file
/// size before anything is allocated, and reading a frame is bounded in time
/// (docs/input-validation.md). Errors (rtd::Error) name the file, frame and channel.
class SequenceReader {
 public:
  static std::unique_ptr<SequenceReader> open(const std::filesystem::path& dir, const SequenceOptions& options = {});
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
  /// Frame `index` (0 <= index < frameCount(), else rtd::Error), with Frame::cut = cutAt(index).
  virtual Frame read(int index) const = 0;
  /// Whether frame `index` starts new history: a cut the sequence marks (`cut` in
  /// sequence.json or cameras.json), one of SequenceOptions::cuts, or a gap in the numbering
  /// before it unless the sequence or the options declare it continuous.
  bool cutAt(int index) const;

  /// Non-guide samples per pixel of supersampling with guide rays (Voorhuis 2018, Sec. 5) that
  /// every frame carries (sequence.json "guideRays", docs/sequence-format.md): spp - 1, or 0.
  virtual int guideRaySampleCount() const { return 0; }
  /// Radiance, depth and normal buffers each of those samples holds.
  virtual std::vector<Buffer> guideRaySampleBuffers() const { return {}; }
  /// Frame `index`'s non-guide samples (include/rtd/guide_rays.h), checked: finite values,
  /// offsets in [-0.5, 0.5]; errors name the file, frame, channel and pixel. rtd::Error when the
  /// sequence has none.
  virtual GuideRaySamples readGuideRaySamples(int index) const;

 protected:
  /// The sequence's own marks: a cut at frame `index`; numbering gaps that are not cuts.
  virtual bool markedCut(int /*index*/) const { return false; }
  virtual bool markedContinuous() const { return false; }
  SequenceOptions options_;  // set by open()

 private:
  static std::unique_ptr<SequenceReader> openKind(const std::filesystem::path& dir);
};

/// Writes a native sequence: frame EXRs and sequence.json. Each file is written to a temporary
/// name and renamed, so an interrupted run never leaves a truncated file.
class SequenceWriter {
 public:
  explicit SequenceWriter(std::filesystem::path dir);
  /// Writes frame_NNNN.exr with every buffer the frame has; remembers its camera and cut.
  /// With `samples` (guide-ray supersampling), the frame is the guide frame and the file also
  /// holds the non-guide samples as layers `sample<k>.<buffer>` and `sample<k>.offset`; every
  /// frame of a sequence has the same number of samples with the same buffers, which must
  /// include color, depth, normal and exactly the frame's radiance buffers.
  /// Throws rtd::Error for a frame number already written or outside [0, kMaxFrameNumber].
  void write(const Frame& frame, const GuideRaySamples* samples = nullptr);
  /// Writes sequence.json describing the frames written so far (call after the last frame,
  /// or after each frame to keep a partial sequence readable).
  void finish() const;
  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
  struct Written {
    int number;
    Camera camera;
    bool cut;
  };
  std::vector<Written> frames_;
  int width_ = 0, height_ = 0;
  std::vector<Buffer> buffers_;
  int guideSamples_ = 0;
  std::vector<Buffer> guideSampleBuffers_;
};

/// Pixel type of written EXR channels.
enum class ExrPixels { Float, Half };

/// Writes an RGB image as an EXR with channels R, G, B (linear), atomically: 32-bit float, or
/// 16-bit half (values beyond 65504 become infinite, as OpenEXR converts them).
void writeRgbExr(const std::filesystem::path& path, const Image& rgb, ExrPixels pixels = ExrPixels::Float);
/// Reads the R, G, B channels of an EXR (single-part, top-level channels).
Image readRgbExr(const std::filesystem::path& path);

/// Worker threads with which OpenEXR decodes and encodes the chunks of the EXR files that
/// readers and writers here read and write (process-wide; rtd::Error outside [0, 4096]). 0, the
/// default, works on the calling thread alone; `rtdenoise denoise` sets its --threads (all cores
/// when 0).
void setExrThreads(int threads);

/// Writes `data` to `path` atomically (temporary file in the same directory, then rename).
void writeFileAtomic(const std::filesystem::path& path, const std::string& data);

/// Every atomic write goes to `<path>.tmp<pid>` first. This removes the temporary files of the
/// writes in progress in this process; it is async-signal-safe, for a SIGINT/SIGTERM handler
/// that then exits (as `rtdenoise` does), so an interrupted run leaves no partial file.
void removeTemporaryFiles() noexcept;

/// Removes the `*.tmp<pid>` files in `dir` that processes which no longer exist left behind
/// (a run killed by SIGKILL or a crash); those of running processes are kept. Returns how
/// many were removed. SequenceWriter calls it on its directory, `rtdenoise denoise` on its output.
int removeStaleTemporaryFiles(const std::filesystem::path& dir);

}  // namespace rtd
