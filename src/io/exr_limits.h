// Reading untrusted EXR files: a check of the header(s) against limits and against the file's
// size, done before OpenEXR parses anything, so a corrupt or hostile file fails fast with a
// message naming it instead of making the reader allocate what its header claims. The checks
// and their reasons are in docs/input-validation.md ("Untrusted files").
#pragma once
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <string>

namespace rtd::exr {

/// Most channels a file may declare (a Blender multilayer frame with every pass has ~100).
constexpr int kMaxChannels = 1024;
/// Most bytes one header attribute may claim (the largest real ones, a preview image or a
/// channel list, are far smaller).
constexpr int64_t kMaxAttributeBytes = int64_t(16) << 20;
/// Longest a file may take to read (header and pixels); past it the read stops with an error.
constexpr std::chrono::seconds kMaxReadTime{60};

/// What the check learned about the file's first part.
struct HeaderCheck {
  int width = 0, height = 0;
  int linesPerChunk = 1;  ///< scanlines per compressed chunk (1 for tiled files)
};

/// Parses the header(s) of the file at `path` without OpenEXR and throws rtd::Error (naming
/// the file and what is wrong) unless: it is a regular file with the EXR magic number and
/// version 2; not deep data; every attribute's size fits in what is left of the file and in
/// kMaxAttributeBytes; the channel list has 1 to kMaxChannels channels of a known type with
/// sampling 1; the data window is a size checkImageSize accepts; the compression is known; the
/// file is long enough for the offset table and chunk headers of every chunk; and the decoded
/// pixels are at most the compression's largest ratio times the file's pixel bytes (exactly
/// their size without compression; no bound for the lossy DWA codecs).
HeaderCheck checkHeader(const std::filesystem::path& path);

/// A deadline for reading one file: check() throws rtd::Error naming the file once it passed.
class ReadDeadline {
 public:
  explicit ReadDeadline(std::string file, std::chrono::steady_clock::duration limit = kMaxReadTime)
      : file_(std::move(file)), limit_(limit), end_(std::chrono::steady_clock::now() + limit) {}
  void check() const;

 private:
  std::string file_;
  std::chrono::steady_clock::duration limit_;
  std::chrono::steady_clock::time_point end_;
};

}  // namespace rtd::exr
