#include "io/image_file.h"

#include <dlfcn.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <fstream>
#include <mutex>

#include "core/validate.h"
#include "io/exr.h"
#include "io/oiio/oiio_plugin.h"
#include "rtd/error.h"

namespace fs = std::filesystem;

namespace rtd::io {

namespace {

struct Plugin {
  RtdOiioInfoFn info = nullptr;
  RtdOiioReadFn read = nullptr;
  std::string why;  // why it did not load
};

/// librtdenoise_oiio, looked for beside this library first (the build tree and an install both
/// put it there), then on the loader's search path; loaded once.
const Plugin& plugin() {
  static Plugin p;
  static std::once_flag once;
  std::call_once(once, [] {
    const char* name = "librtdenoise_oiio.so";
    std::vector<std::string> candidates;
    Dl_info self{};
    if (dladdr(reinterpret_cast<void*>(&otherFormatsAvailable), &self) && self.dli_fname)
      candidates.push_back((fs::path(self.dli_fname).parent_path() / name).string());
    candidates.push_back(name);
    for (const auto& c : candidates) {
      void* h = dlopen(c.c_str(), RTLD_NOW | RTLD_LOCAL);
      if (!h) {
        if (p.why.empty()) p.why = dlerror();
        continue;
      }
      p.info = reinterpret_cast<RtdOiioInfoFn>(dlsym(h, "rtd_oiio_info"));
      p.read = reinterpret_cast<RtdOiioReadFn>(dlsym(h, "rtd_oiio_read"));
      if (p.info && p.read) return;
      p.why = c + " lacks rtd_oiio_info / rtd_oiio_read";
    }
    p.info = nullptr;
    p.read = nullptr;
  });
  return p;
}

ImageFile readExr(const fs::path& path, const std::string& context) {
  const exr::Header h = exr::readHeader(path);
  const auto has = [&](const char* c) { return std::find(h.channels.begin(), h.channels.end(), c) != h.channels.end(); };
  static const std::vector<std::vector<const char*>> kLayouts = {{"R", "G", "B"}, {"R", "G"}, {"X", "Y", "Z"},
                                                                 {"X", "Y"},      {"Y"},      {"Z"},
                                                                 {"V"}};
  std::vector<std::string> names;
  for (const auto& layout : kLayouts)
    if (std::all_of(layout.begin(), layout.end(), has)) {
      names.assign(layout.begin(), layout.end());
      break;
    }
  if (names.empty() && h.channels.size() == 1) names = h.channels;
  if (names.empty()) {
    std::string list;
    for (const auto& c : h.channels) list += (list.empty() ? "" : ", ") + c;
    throw Error(context + ", file '" + path.string() + "': channels " + list +
                " are none of R,G,B / R,G / X,Y,Z / X,Y / Y / Z / V, nor a single channel");
  }
  const auto planes = exr::readChannels(path, names, context);
  ImageFile f;
  f.image = Image(h.width, h.height, int(names.size()));
  for (size_t i = 0; i < size_t(h.width) * h.height; ++i)
    for (size_t c = 0; c < names.size(); ++c) f.image.pixels[i * names.size() + c] = planes[c][i];
  return f;
}

// A PNG's chunk list, checked before OpenImageIO sees the file: the signature, then chunks of
// (4-byte big-endian length, type, data, CRC) up to IEND, each inside the file. OpenImageIO 2.4's
// PNG reader hits the end of a truncated file inside libpng, whose error longjmps over its C++
// frames (a leaked message string per file, found by fuzz_per_buffer); a truncated or garbled
// chunk list is refused here with a message saying where, instead.
void checkPngChunks(const fs::path& path, const std::string& where) {
  std::ifstream in(path, std::ios::binary);
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (!in || ec) throw Error(where + ": cannot open it");
  static constexpr std::array<unsigned char, 8> kSignature = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  std::array<unsigned char, 8> head{};
  if (!in.read(reinterpret_cast<char*>(head.data()), 8) || head != kSignature) throw Error(where + ": not a PNG (no PNG signature)");
  std::uintmax_t at = 8;
  for (int chunk = 0;; ++chunk) {
    if (size - at < 12 || !in.read(reinterpret_cast<char*>(head.data()), 8))
      throw Error(where + ": the PNG is truncated (it ends at byte " + std::to_string(size) + " without an IEND chunk)");
    const uint32_t length = uint32_t(head[0]) << 24 | uint32_t(head[1]) << 16 | uint32_t(head[2]) << 8 | head[3];
    const std::string type(reinterpret_cast<const char*>(&head[4]), 4);
    if (length > 0x7fffffffu || !std::all_of(type.begin(), type.end(), [](unsigned char c) { return std::isalpha(c); }))
      throw Error(where + ": the PNG's chunk " + std::to_string(chunk) + " at byte " + std::to_string(at) + " is garbled");
    if (length + std::uintmax_t(12) > size - at)
      throw Error(where + ": the PNG is truncated (chunk '" + type + "' at byte " + std::to_string(at) + " claims " +
                  std::to_string(length) + " bytes, the file ends at " + std::to_string(size) + ")");
    if (type == "IEND") return;
    at += length + std::uintmax_t(12);
    in.seekg(std::streamoff(at));
  }
}

}  // namespace

bool otherFormatsAvailable() { return plugin().info != nullptr; }

ImageFile readImageFile(const fs::path& path, const std::string& context) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
  if (ext == ".exr") return readExr(path, context);
  const Plugin& p = plugin();
  const std::string where = context + ", file '" + path.string() + "'";
  if (!p.info)
    throw Error(where + ": reading " + ext + " files needs OpenImageIO (librtdenoise_oiio.so, built when "
                "libopenimageio-dev is installed), which did not load: " + p.why + ". Convert the file to EXR.");
  if (ext == ".png") checkPngChunks(path, where);
  RtdOiioInfo info{};
  char error[512] = {};
  if (p.info(path.c_str(), &info, error, sizeof error) != 0) throw Error(where + ": " + error);
  checkImageSize(where + ": the image", info.width, info.height);
  if (info.channels < 1 || info.channels > 64)
    throw Error(where + ": " + std::to_string(info.channels) + " channels (1 to 64 are read)");
  ImageFile f;
  f.image = Image(info.width, info.height, info.channels);
  f.integer = info.integer != 0;
  f.srgb = info.srgb != 0;
  if (p.read(path.c_str(), &info, f.image.pixels.data(), error, sizeof error) != 0) throw Error(where + ": " + error);
  return f;
}

}  // namespace rtd::io
