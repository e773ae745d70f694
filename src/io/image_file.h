// One image per file, in any format rtdenoise reads: EXR with OpenEXR, everything else (PFM,
// HDR, PNG, TIFF, ...) with OpenImageIO through librtdenoise_oiio (src/io/oiio/oiio_plugin.h).
#pragma once
#include <filesystem>
#include <string>

#include "rtd/image.h"

namespace rtd::io {

struct ImageFile {
  Image image;           ///< floats, rows from the top, the file's channels interleaved
  bool integer = false;  ///< stored as integers (PNG, 8/16-bit TIFF): values in [0, 1]
  bool srgb = false;     ///< the values are sRGB-encoded (OpenImageIO's "oiio:ColorSpace")
};

/// Reads `path`. EXR: its channels R, G, B (or R, G / X, Y, Z / X, Y / Y / Z / V, or its only
/// channel), as found. Other formats: every channel, through OpenImageIO. The size is checked
/// (checkImageSize) before the pixels are allocated. Errors (rtd::Error) start with `context`
/// and name the file.
ImageFile readImageFile(const std::filesystem::path& path, const std::string& context);

/// Whether readImageFile() can read formats other than EXR in this installation (whether
/// librtdenoise_oiio loads).
bool otherFormatsAvailable();

}  // namespace rtd::io
