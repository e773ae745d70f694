// The CPU backend's copy of one frame: every provided buffer as float planes.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "core/plane.h"
#include "core/sanitize.h"
#include "rtd/frame.h"
#include "rtd/methods/reprojection.h"

namespace rtd {

struct FrameData {
  int width = 0;
  int height = 0;
  std::array<std::vector<Plane>, kBufferCount> buffers;  // empty vector where absent
  Camera camera;

  bool has(Buffer b) const { return !buffers[int(b)].empty(); }
  const Plane& plane(Buffer b, int c = 0) const { return buffers[int(b)][c]; }
  Plane& plane(Buffer b, int c = 0) { return buffers[int(b)][c]; }
  /// The three planes of an RGB/XYZ buffer.
  const std::vector<Plane>& planes(Buffer b) const { return buffers[int(b)]; }
  /// Bytes of the imported planes.
  uint64_t bytes() const {
    uint64_t n = 0;
    for (const auto& buffer : buffers)
      for (const Plane& p : buffer) n += uint64_t(p.size()) * sizeof(float);
    return n;
  }
};

/// True for buffers holding radiance.
bool isRadianceBuffer(Buffer b);

/// The buffers a method imports when the frame has them, on either backend: its required and
/// extra ones plus what the shared passes read (demodulation, emission, and the reprojection
/// guides whose tests these settings turn on: depth and object ids only where tested, world
/// positions where tested or where the frame has no motion vectors to reproject by).
std::vector<Buffer> importedBuffers(const std::vector<Buffer>& required, const std::vector<Buffer>& extra,
                                    const ReprojectionSettings& reprojection, bool frameHasMotion);

/// Copies the views of `in` into `out` (reusing its allocations): only the buffers in `used`
/// (all of them if null), so a frame carrying many buffers costs only what the method reads.
/// Checks the views first (checkInputViews: required buffers present, one size, formats,
/// alignment, strides); throws rtd::Error naming the buffer otherwise. Every value is
/// sanitized on the way (core/sanitize.h: non-finite to 0, clamped into its buffer's range),
/// and in the same pass over each row unit vectors are renormalized (renormalizeRow) and
/// emission is separated (subtractEmissionRow); then the hidden area is cleared
/// (applyHiddenArea). Returns the number of values replaced; `counts`, if given, receives them
/// per buffer.
uint64_t importFrame(const FrameInputs& in, const std::vector<Buffer>& required, FrameData& out,
                     const std::vector<Buffer>* used = nullptr, SanitizeStats* counts = nullptr);

/// One row of Color, Direct or Diffuse (three channel rows v) less Buffer::Emission's row e,
/// clamped at 0 and flushed (core/flush.h), so methods filter only the noisy part: importFrame()
/// applies it on the way in (the float rows' kernel does the same, RowFixes::emission).
void subtractEmissionRow(float* const* v, const float* const* e, int w);

/// Buffer::HiddenArea (if present): the pixels the lens hides carry nothing. Their radiance
/// buffers and normals become 0, so every method treats them as background (a zero normal
/// weighs 0 in the spatial filters) and they neither take nor give light; importFrame() calls it.
void applyHiddenArea(FrameData& frame);

/// Whether a pass writing `bytes` of pixels that the next passes will not read right away
/// writes them around the caches (non-temporal stores): when they exceed what a last-level
/// cache could keep (8 MiB), it saves reading every destination line before overwriting it.
/// Import and export use it.
bool streamsPastCache(size_t bytes);

/// The frame's output view, filled row by row from linear RGB rows plus the separated emission
/// (if not null): alpha 1 in Float4 and Half4 views, halves through exportHalfRow() (core/half.h).
/// exportRgb() runs it over whole planes; a pass that computes the output row by row (TAA) hands
/// each row over while it is still in cache, instead of storing planes for a pass to read back.
class RgbExport {
 public:
  /// Throws rtd::Error unless `out` is a Float3, Float4, Half3 or Half4 view of width x height.
  RgbExport(const ImageView& out, int width, int height, const std::vector<Plane>* emission);
  /// Row y of the output from rgb[0..2] (width floats each); any thread, each row once.
  void row(int y, const float* const rgb[3]) const;

 private:
  ImageView out_;
  const std::vector<Plane>* emission_;
  bool half_, packed_, stream_;
};

/// Writes RGB planes, plus the separated emission if not null, into `out` (RgbExport).
void exportRgb(const Plane3& rgb, const std::vector<Plane>* emission, const ImageView& out);

}  // namespace rtd
