// librtdenoise_oiio: image files read with OpenImageIO (src/io/oiio/oiio_plugin.h).
#include "io/oiio/oiio_plugin.h"

#include <OpenImageIO/imageio.h>
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/strutil.h>

#include <cstdio>
#include <memory>
#include <string>

namespace {
int fail(char* error, int size, const std::string& message) {
  std::snprintf(error, size_t(size), "%s", message.c_str());
  return -1;
}
// Opens `path` with the reader of the format its extension names, and only that one:
// ImageInput::open(path) would, when that reader refuses the file, try every other format in
// turn, OpenEXR among them, and so read an EXR named .png without the header checks rtdenoise
// makes on EXR files (src/io/exr_limits.h; a fuzz finding). Creating the reader from the
// extension alone does not look at the file.
std::unique_ptr<OIIO::ImageInput> openByExtension(const char* path, std::string& error) {
  const std::string ext = OIIO::Filesystem::extension(path, false);
  auto in = OIIO::ImageInput::create(ext);
  if (!in) {
    error = "no OpenImageIO reader for '." + ext + "' files: " + OIIO::geterror();
    return nullptr;
  }
  OIIO::ImageSpec spec;
  if (!in->open(path, spec)) {
    error = in->geterror();
    if (error.empty()) error = "OpenImageIO's " + std::string(in->format_name()) + " reader cannot read it";
    return nullptr;
  }
  return in;
}
}  // namespace

extern "C" __attribute__((visibility("default"))) int rtd_oiio_info(const char* path, RtdOiioInfo* info, char* error,
                                                                    int errorSize) {
  std::string why;
  auto in = openByExtension(path, why);
  if (!in) return fail(error, errorSize, why);
  const OIIO::ImageSpec& spec = in->spec();
  info->width = spec.width;
  info->height = spec.height;
  info->channels = spec.nchannels;
  info->integer = spec.format.is_floating_point() ? 0 : 1;
  const std::string space = spec.get_string_attribute("oiio:ColorSpace");
  info->srgb = OIIO::Strutil::iequals(space, "sRGB") ? 1 : 0;
  if (spec.depth > 1) return fail(error, errorSize, "a volume image (depth " + std::to_string(spec.depth) + ")");
  return 0;
}

extern "C" __attribute__((visibility("default"))) int rtd_oiio_read(const char* path, const RtdOiioInfo* expected,
                                                                    float* pixels, char* error, int errorSize) {
  std::string why;
  auto in = openByExtension(path, why);
  if (!in) return fail(error, errorSize, why);
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width != expected->width || spec.height != expected->height || spec.nchannels != expected->channels ||
      spec.depth > 1)
    return fail(error, errorSize, "the file changed while it was read");
  if (!in->read_image(0, 0, 0, in->spec().nchannels, OIIO::TypeDesc::FLOAT, pixels))
    return fail(error, errorSize, in->geterror());
  return 0;
}
