// Thin OpenEXR helpers shared by the sequence reader and writer. Errors become rtd::Error with
// the file name.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace rtd::exr {

struct Header {
  int width = 0, height = 0;
  std::vector<std::string> channels;  // names as stored
};

/// Reads the header; throws rtd::Error if the file is missing, not an EXR, or corrupt.
Header readHeader(const std::filesystem::path& path);

/// Reads the named channels as floats, each a width*height plane (rows from the top), all in
/// one pass over the file (a name may repeat).
/// `context` prefixes error messages (e.g. "frame 3"). Missing channels and truncated pixel
/// data throw rtd::Error naming the file and the channel.
std::vector<std::vector<float>> readChannels(const std::filesystem::path& path, const std::vector<std::string>& names,
                                             const std::string& context);

/// Worker threads of OpenEXR's process-wide pool, which decodes and encodes the chunks of every
/// file read or written here in parallel (rtd::setExrThreads).
void setThreads(int threads);

/// One channel to write: a name and interleaved data with a stride (in floats).
struct ChannelSource {
  std::string name;
  const float* data;
  size_t stride;  // floats between horizontally adjacent pixels
};

/// Writes the channels (ZIP compression) atomically: temporary file, then rename. `half`:
/// stored as 16-bit HALF (converted from the float data by OpenEXR), else 32-bit FLOAT.
void writeChannels(const std::filesystem::path& path, int width, int height, const std::vector<ChannelSource>& channels,
                   bool half = false);

}  // namespace rtd::exr
