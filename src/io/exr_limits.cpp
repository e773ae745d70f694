#include "io/exr_limits.h"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <vector>

#include "core/validate.h"
#include "rtd/error.h"

namespace rtd::exr {

namespace fs = std::filesystem;

namespace {

// The header as a byte stream that never reads past the end of the file.
class HeaderStream {
 public:
  HeaderStream(const fs::path& path, std::uintmax_t size) : in_(path, std::ios::binary), size_(size) {}
  bool ok() const { return bool(in_); }
  std::uintmax_t offset() const { return offset_; }
  std::uintmax_t remaining() const { return size_ - offset_; }

  void bytes(void* dst, size_t n, const char* what) {
    if (n > remaining()) fail(std::string("the file ends inside ") + what);
    in_.read(static_cast<char*>(dst), std::streamsize(n));
    if (!in_) fail(std::string("cannot read ") + what);
    offset_ += n;
  }
  void skip(std::uintmax_t n, const char* what) {
    if (n > remaining()) fail(std::string("the file ends inside ") + what);
    in_.seekg(std::streamoff(n), std::ios::cur);
    offset_ += n;
  }
  int32_t int32(const char* what) {
    unsigned char b[4];
    bytes(b, 4, what);
    return int32_t(uint32_t(b[0]) | uint32_t(b[1]) << 8 | uint32_t(b[2]) << 16 | uint32_t(b[3]) << 24);
  }
  /// A null-terminated string of at most `maxLength` characters.
  std::string text(size_t maxLength, const char* what) {
    std::string s;
    for (;;) {
      char c;
      bytes(&c, 1, what);
      if (c == '\0') return s;
      if (s.size() == maxLength) fail(std::string(what) + " is longer than " + std::to_string(maxLength) + " characters");
      s += c;
    }
  }
  [[noreturn]] static void fail(const std::string& what) { throw Error(what); }

 private:
  std::ifstream in_;
  std::uintmax_t size_, offset_ = 0;
};

int32_t readInt(const std::vector<unsigned char>& v, size_t at) {
  return int32_t(uint32_t(v[at]) | uint32_t(v[at + 1]) << 8 | uint32_t(v[at + 2]) << 16 | uint32_t(v[at + 3]) << 24);
}

// Scanlines per chunk of each compression (OpenEXR's file layout), and the largest ratio of
// decoded to stored bytes it can reach: NONE stores the pixels as they are; RLE at most 128
// bytes in 2; the zlib-based codecs (ZIPS, ZIP, PXR24 with its 24-bit floats) at most
// deflate's 1032:1 times 4/3, PIZ less (measured on zero images: RLE 63, ZIP 991, PXR24 1304,
// PIZ 405), B44/B44A at most 32:6. The lossy DWA codecs reach 6000:1 on flat images and have
// no useful bound (0).
struct Codec {
  int linesPerChunk;
  double maxRatio;
};
constexpr Codec kCodecs[] = {{1, 1.0},  {1, 128.0},  {1, 2048.0}, {16, 2048.0}, {32, 2048.0},
                             {16, 2048.0}, {32, 16.0}, {32, 16.0},  {32, 0.0},    {256, 0.0}};

// OpenEXR reads an attribute of a type it knows by that type's own layout, not by the size the
// header gives: a box2i takes 16 bytes whatever the header claims, and the next attribute is
// then read from the wrong place (where a mutated file makes it an opaque attribute claiming
// gigabytes). So the fixed-size types must claim exactly their size, and the variable ones
// (string vector, preview image) must be consistent with theirs. The list is OpenEXR 3.1's
// known attribute types (ImfStandardAttributes / Attribute::knownType). The channel list, also
// read by content, is checked by parseChannels.
struct FixedType {
  const char* name;
  int32_t bytes;
};
constexpr FixedType kFixedTypes[] = {
    {"box2i", 16},      {"box2f", 16},       {"chromaticities", 32}, {"compression", 1}, {"double", 8},
    {"envmap", 1},      {"float", 4},        {"int", 4},             {"keycode", 28},    {"lineOrder", 1},
    {"m33f", 36},       {"m33d", 72},        {"m44f", 64},           {"m44d", 128},      {"rational", 8},
    {"tiledesc", 9},    {"timecode", 8},     {"v2i", 8},             {"v2f", 8},         {"v2d", 16},
    {"v3i", 12},        {"v3f", 12},         {"v3d", 24},            {"deepImageState", 1}};

void checkTypedSize(const std::string& type, int32_t bytes, const std::vector<unsigned char>& value, const std::string& what) {
  for (const FixedType& t : kFixedTypes)
    if (type == t.name && bytes != t.bytes)
      HeaderStream::fail(what + " of type " + type + " claims " + std::to_string(bytes) + " bytes; that type has " +
                         std::to_string(t.bytes));
  if (type == "idmanifest" && bytes < 4)  // its uncompressed size, then size - 4 bytes of data
    HeaderStream::fail(what + " of type idmanifest claims " + std::to_string(bytes) + " bytes, fewer than its 4-byte size field");
  if (type == "stringvector") {  // strings of (int length, characters) filling the value exactly
    size_t at = 0;
    while (at < value.size()) {
      if (value.size() - at < 4) HeaderStream::fail(what + ": a string vector ends inside a length");
      const int32_t n = readInt(value, at);
      at += 4;
      if (n < 0 || size_t(n) > value.size() - at) HeaderStream::fail(what + ": a string of the vector claims " + std::to_string(n) + " bytes, more than the attribute has");
      at += size_t(n);
    }
  } else if (type == "preview") {  // width, height, then width x height RGBA bytes
    if (value.size() < 8) HeaderStream::fail(what + ": a preview image needs at least 8 bytes");
    const int64_t w = uint32_t(readInt(value, 0)), h = uint32_t(readInt(value, 4));
    if (8 + 4 * w * h != int64_t(value.size()))
      HeaderStream::fail(what + ": a " + std::to_string(w) + "x" + std::to_string(h) + " preview image does not fit its " +
                         std::to_string(value.size()) + " bytes");
  }
}

struct Part {
  bool haveChannels = false, haveWindow = false, tiled = false, deep = false;
  int compression = 0;
  int64_t width = 0, height = 0;
  int64_t bytesPerPixel = 0;  // decoded, all channels
  int64_t tileX = 0, tileY = 0;
};

void parseChannels(const std::vector<unsigned char>& v, Part& part) {
  size_t at = 0;
  int count = 0;
  for (;;) {
    if (at >= v.size()) HeaderStream::fail("the channel list is not terminated");
    if (v[at] == 0) break;
    const auto* name = reinterpret_cast<const char*>(&v[at]);
    const size_t len = strnlen(name, v.size() - at);
    if (at + len + 1 + 16 > v.size()) HeaderStream::fail("the channel list is truncated");
    const std::string channel(name, len);
    at += len + 1;
    const int32_t type = readInt(v, at), xs = readInt(v, at + 8), ys = readInt(v, at + 12);
    at += 16;
    if (type < 0 || type > 2) HeaderStream::fail("channel '" + channel + "' has an unknown pixel type " + std::to_string(type));
    if (xs != 1 || ys != 1)
      HeaderStream::fail("channel '" + channel + "' is subsampled (" + std::to_string(xs) + "x" + std::to_string(ys) +
                         "), which rtdenoise does not read");
    part.bytesPerPixel += type == 1 ? 2 : 4;  // HALF; UINT and FLOAT are 4 bytes
    if (++count > kMaxChannels)
      HeaderStream::fail("the file declares more than " + std::to_string(kMaxChannels) + " channels");
  }
  // OpenEXR reads the list up to its terminating null, whatever size it claims: bytes after
  // it would be read as the next attribute (a fuzz finding, tests/fixtures/fuzz/native_sequence).
  if (at + 1 != v.size())
    HeaderStream::fail("the channel list ends at byte " + std::to_string(at + 1) + " of the " + std::to_string(v.size()) +
                       " it claims");
  if (count == 0) HeaderStream::fail("the file has no channels");
  part.haveChannels = true;
}

}  // namespace

HeaderCheck checkHeader(const fs::path& path) {
  const std::string file = "file '" + path.string() + "'";
  std::error_code ec;
  if (!fs::exists(path, ec)) throw Error(file + " does not exist");
  if (!fs::is_regular_file(path, ec)) throw Error(file + " is not a regular file");
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw Error(file + ": cannot read its size (" + ec.message() + ")");
  try {
    HeaderStream in(path, size);
    if (!in.ok()) throw Error("cannot open it");
    if (size < 8) throw Error("it is too short to be an EXR (" + std::to_string(size) + " bytes)");
    if (in.int32("the magic number") != 20000630) throw Error("it is not an EXR (no EXR magic number)");
    const int32_t version = in.int32("the version");
    if ((version & 0xff) != 2) throw Error("EXR version " + std::to_string(version & 0xff) + " is not supported");
    const bool longNames = version & 0x400, multipart = version & 0x1000;
    if (version & 0x800 && !multipart) throw Error("deep EXR data is not supported");
    const size_t maxName = longNames ? 255 : 31;

    std::vector<Part> parts;  // one, or the single part of a multi-part file
    for (;;) {
      Part part;
      part.tiled = (version & 0x200) != 0;
      int attributes = 0;
      for (;;) {
        const std::string name = in.text(maxName, "an attribute name");
        if (name.empty()) break;
        const std::string type = in.text(maxName, "an attribute type");
        const int32_t bytes = in.int32("an attribute size");
        const std::string what = "header attribute '" + name + "'";
        if (bytes < 0 || bytes > kMaxAttributeBytes || std::uintmax_t(bytes) > in.remaining())
          throw Error(what + " claims " + std::to_string(bytes) + " bytes, but " +
                      (bytes < 0 ? std::string("sizes cannot be negative")
                                 : "only " + std::to_string(std::min<std::uintmax_t>(in.remaining(), uintmax_t(kMaxAttributeBytes))) +
                                       " can be read (the rest of the file, at most 16 MiB an attribute)"));
        if (++attributes > 4096) throw Error("a header has more than 4096 attributes");
        if (name == "channels" && type == "chlist") {
          std::vector<unsigned char> v(static_cast<size_t>(bytes));
          in.bytes(v.data(), v.size(), what.c_str());
          parseChannels(v, part);
        } else if (name == "dataWindow" && type == "box2i" && bytes == 16) {
          const int64_t x0 = in.int32("dataWindow"), y0 = in.int32("dataWindow"), x1 = in.int32("dataWindow"),
                        y1 = in.int32("dataWindow");
          part.width = x1 - x0 + 1;
          part.height = y1 - y0 + 1;
          part.haveWindow = true;
        } else if (name == "compression" && type == "compression" && bytes == 1) {
          unsigned char c;
          in.bytes(&c, 1, what.c_str());
          if (c >= std::size(kCodecs)) throw Error("unknown compression " + std::to_string(int(c)));
          part.compression = c;
        } else if (name == "tiles" && type == "tiledesc" && bytes == 9) {
          part.tileX = uint32_t(in.int32("tiles"));
          part.tileY = uint32_t(in.int32("tiles"));
          in.skip(1, what.c_str());
          part.tiled = true;
        } else if (name == "type" && type == "string") {
          std::string t(static_cast<size_t>(bytes), '\0');
          in.bytes(t.data(), t.size(), what.c_str());
          if (t.rfind("deep", 0) == 0) throw Error("deep EXR data is not supported");
          part.tiled = t == "tiledimage";
        } else if (type == "stringvector" || type == "preview") {
          std::vector<unsigned char> v(static_cast<size_t>(bytes));
          in.bytes(v.data(), v.size(), what.c_str());
          checkTypedSize(type, bytes, v, what);
        } else {
          checkTypedSize(type, bytes, {}, what);
          in.skip(std::uintmax_t(bytes), what.c_str());
        }
      }
      if (!part.haveChannels) throw Error("a header has no channel list");
      if (!part.haveWindow) throw Error("a header has no data window");
      if (part.tiled && (part.tileX < 1 || part.tileY < 1 || part.tileX > kMaxImageSide || part.tileY > kMaxImageSide))
        throw Error("tile size " + std::to_string(part.tileX) + "x" + std::to_string(part.tileY) + " is not valid");
      checkImageSize("the data window", part.width, part.height);
      parts.push_back(part);
      if (!multipart) break;
      // Multi-part: an empty header (one null byte) ends the list of headers.
      char next;
      in.bytes(&next, 1, "the list of headers");
      if (next == '\0') break;
      throw Error("multi-part EXR files with more than one part are not supported");
    }

    // Every chunk needs its offset-table entry (8 bytes) and its chunk header (scanline: y and
    // size, 8 bytes; tile: 4 coordinates and size, 20; +4 for the part number in multi-part
    // files); the decoded pixels are bounded by the codec's ratio.
    const Part& p = parts.front();
    const Codec codec = kCodecs[p.compression];
    const int64_t chunks = p.tiled ? ((p.width + p.tileX - 1) / p.tileX) * ((p.height + p.tileY - 1) / p.tileY)
                                   : (p.height + codec.linesPerChunk - 1) / codec.linesPerChunk;
    const int64_t perChunk = 8 + (p.tiled ? 20 : 8) + (multipart ? 4 : 0);
    const std::uintmax_t headerEnd = in.offset();
    if (headerEnd + std::uintmax_t(chunks * perChunk) > size)
      throw Error("it is truncated: " + std::to_string(chunks) + " chunks of pixels need at least " +
                  std::to_string(headerEnd + std::uintmax_t(chunks * perChunk)) + " bytes, the file has " + std::to_string(size));
    const double pixelBytes = double(size - headerEnd - std::uintmax_t(chunks * perChunk));
    const double decoded = double(p.width) * double(p.height) * double(p.bytesPerPixel);
    if (codec.maxRatio > 0 && decoded > codec.maxRatio * pixelBytes + 64.0 * double(chunks))
      throw Error("its header claims " + std::to_string(p.width) + "x" + std::to_string(p.height) + " pixels of " +
                  std::to_string(p.bytesPerPixel) + " bytes, more than its " + std::to_string(uintmax_t(pixelBytes)) +
                  " bytes of pixel data can hold with its compression");
    return {int(p.width), int(p.height), p.tiled ? 1 : codec.linesPerChunk};
  } catch (const Error& e) {
    throw Error(file + ": " + e.what());
  }
}

void ReadDeadline::check() const {
  if (std::chrono::steady_clock::now() > end_)
    throw Error(file_ + ": reading took longer than " +
                std::to_string(std::chrono::duration_cast<std::chrono::seconds>(limit_).count()) +
                " s, the limit for one file (a corrupt file, or a stalled file system)");
}

}  // namespace rtd::exr
