// Native, per-buffer and Blender sequence readers, the native writer, and RGB EXR helpers.
#include "rtd/sequence.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <nlohmann/json.hpp>
#include <cmath>
#include <map>
#include <optional>
#include <regex>
#include <set>
#include <sstream>
#include <tuple>

#include "core/validate.h"
#include "io/exr.h"
#include "io/image_file.h"
#include "io/small_file.h"
#include "io/temp_files.h"
#include "core/frame_data.h"
#include "passes/tonemap.h"
#include "rtd/error.h"
#include "rtd/guide_rays.h"

namespace rtd {

namespace fs = std::filesystem;
using nlohmann::json;

// ---------------------------------------------------------------------------------------------
// Shared helpers

FrameInputs Frame::inputs() const {
  FrameInputs in;
  for (int i = 0; i < kBufferCount; ++i)
    if (!buffers[i].empty()) in.buffers[i] = buffers[i].view();
  in.camera = camera;
  in.cameraCut = cut;
  return in;
}

/// EXR channel names of a buffer in the native format: "<name>.<C>", "id" for id channels.
static std::vector<std::string> nativeChannelNames(Buffer b) {
  std::vector<std::string> names;
  for (char c : bufferChannels(b))
    names.push_back(std::string(bufferName(b)) + "." + (c == 'I' ? std::string("id") : std::string(1, c)));
  return names;
}

/// Planes [first, first + count) as one interleaved image.
static Image interleave(const std::vector<std::vector<float>>& planes, size_t first, size_t count, int w, int h) {
  Image img(w, h, int(count));
  for (size_t c = 0; c < count; ++c) {
    const std::vector<float>& plane = planes[first + c];
    for (size_t i = 0; i < size_t(w) * h; ++i) img.pixels[i * count + c] = plane[i];
  }
  return img;
}
static Image interleave(const std::vector<std::vector<float>>& planes, int w, int h) {
  return interleave(planes, 0, planes.size(), w, h);
}

static std::array<float, 16> matrixFromJson(const json& j, const std::string& where) {
  std::array<float, 16> m{};
  std::vector<const json*> flat;
  if (j.is_array() && j.size() == 4 && j[0].is_array()) {
    for (const auto& row : j) {
      if (!row.is_array()) throw Error(where + ": a camera matrix needs 16 numbers");
      for (const auto& v : row) flat.push_back(&v);
    }
  } else if (j.is_array()) {
    for (const auto& v : j) flat.push_back(&v);
  }
  if (flat.size() != 16) throw Error(where + ": a camera matrix needs 16 numbers");
  for (size_t i = 0; i < 16; ++i) {
    if (!flat[i]->is_number()) throw Error(where + ": a camera matrix needs 16 numbers");
    m[i] = flat[i]->get<float>();
    if (!std::isfinite(m[i])) throw Error(where + ": camera matrix entry " + std::to_string(i) + " is not a finite float");
  }
  return m;
}

// sequence.json and cameras.json are small; a larger file is not one of them.
constexpr std::uintmax_t kMaxJsonBytes = std::uintmax_t(64) << 20;

static json readJson(const fs::path& path) {
  const std::string text = readSmallFile(path, kMaxJsonBytes, "'" + path.string() + "'");
  try {
    return json::parse(text);
  } catch (const std::exception& e) {
    throw Error("'" + path.string() + "' is not valid JSON: " + e.what());
  }
}

// A frame number given in a file: an integer in [0, kMaxFrameNumber].
static int frameNumberFromJson(const json& v, const std::string& where) {
  if (!v.is_number_integer() || (v.is_number_unsigned() ? v.get<uint64_t>() > uint64_t(kMaxFrameNumber)
                                                          : v.get<int64_t>() < 0 || v.get<int64_t>() > kMaxFrameNumber))
    throw Error(where + ": frame number " + v.dump() + " is not an integer in [0, " + std::to_string(kMaxFrameNumber) + "]");
  return int(v.get<int64_t>());
}

// A frame number written as text (a file name's digits, a cameras.json key), checked the same way.
static std::optional<int> frameNumberFromText(std::string_view digits) {
  if (digits.empty() || digits.size() > 10) return std::nullopt;
  int64_t n = 0;
  for (char c : digits) {
    if (c < '0' || c > '9') return std::nullopt;
    n = n * 10 + (c - '0');
  }
  if (n > kMaxFrameNumber) return std::nullopt;
  return int(n);
}

static bool boolField(const json& j, const char* key, const std::string& where) {
  if (!j.contains(key)) return false;
  if (!j[key].is_boolean()) throw Error(where + ": field '" + key + "' must be true or false");
  return j[key].get<bool>();
}

bool SequenceReader::cutAt(int index) const {
  if (index < 0 || index >= frameCount()) return false;
  const int n = frameNumber(index);
  if (markedCut(index) || std::find(options_.cuts.begin(), options_.cuts.end(), n) != options_.cuts.end()) return true;
  return index > 0 && !options_.continuous && !markedContinuous() && int64_t(n) != int64_t(frameNumber(index - 1)) + 1;
}

// rtd::Error unless 0 <= index < count.
static void checkIndex(int index, int count, const fs::path& dir) {
  if (index < 0 || index >= count)
    throw Error("sequence '" + dir.string() + "': frame index " + std::to_string(index) + " is out of range (it has " +
                std::to_string(count) + " frames)");
}

// ---------------------------------------------------------------------------------------------
// Guide-ray samples in native frames (docs/sequence-format.md, "Guide-ray samples")

constexpr int kMaxGuideRaySamples = 64;

// Layer of non-guide sample k (1-based): "sample<k>.<buffer>.<C>", and its offset "sample<k>.offset.X/Y".
static std::vector<std::string> sampleChannelNames(int k, Buffer b) {
  std::vector<std::string> names = nativeChannelNames(b);
  for (std::string& n : names) n = "sample" + std::to_string(k) + "." + n;
  return names;
}
static std::vector<std::string> sampleOffsetChannelNames(int k) {
  const std::string prefix = "sample" + std::to_string(k) + ".offset.";
  return {prefix + "X", prefix + "Y"};
}

// What the samples of a frame with `frame` buffers must hold: color, depth and normal, and
// exactly the frame's radiance buffers (GuideRays::premix mixes all of them or none), nothing
// else. Empty when they do, else what is wrong.
static std::string guideSampleBuffersProblem(const std::vector<Buffer>& samples, const std::vector<Buffer>& frame) {
  auto has = [](const std::vector<Buffer>& list, Buffer b) { return std::find(list.begin(), list.end(), b) != list.end(); };
  for (Buffer b : {Buffer::Color, Buffer::Depth, Buffer::Normal})
    if (!has(samples, b)) return "the samples have no '" + std::string(bufferName(b)) + "' buffer";
  for (Buffer b : samples)
    if (!isRadianceBuffer(b) && b != Buffer::Depth && b != Buffer::Normal)
      return "buffer '" + std::string(bufferName(b)) + "' is not one a sample carries (radiance, depth, normal)";
  for (int i = 0; i < kBufferCount; ++i)
    if (isRadianceBuffer(Buffer(i)) && has(frame, Buffer(i)) != has(samples, Buffer(i)))
      return "radiance buffer '" + std::string(bufferName(Buffer(i))) + "' is in the " +
             (has(frame, Buffer(i)) ? "frames but not in the samples" : "samples but not in the frames");
  return "";
}

GuideRaySamples SequenceReader::readGuideRaySamples(int index) const {
  throw Error("frame index " + std::to_string(index) + ": this " + std::string(sequenceKindName(kind())) +
              " sequence carries no guide-ray samples");
}

void writeFileAtomic(const fs::path& path, const std::string& data) {
  TemporaryFile tmp(path);
  {
    std::ofstream out(tmp.path(), std::ios::binary);
    out << data;
    out.flush();
    if (!out) throw Error("cannot write '" + path.string() + "'");
  }
  tmp.commit();
}

/// Frame number from a file name: the last run of digits (frame_0012.exr -> 12); none if the
/// name has no digits; rtd::Error if they are not a number in [0, kMaxFrameNumber].
static std::optional<int> frameNumberOf(const fs::path& p) {
  static const std::regex digits("(\\d+)(?!.*\\d)");
  std::smatch m;
  std::string stem = p.stem().string();
  if (!std::regex_search(stem, m, digits)) return std::nullopt;
  auto n = frameNumberFromText(m[1].str());
  if (!n)
    throw Error("file '" + p.string() + "': frame number " + m[1].str() + " is out of range [0, " +
                std::to_string(kMaxFrameNumber) + "]");
  return n;
}

// ---------------------------------------------------------------------------------------------
// Native format

namespace {

class NativeReader final : public SequenceReader {
 public:
  explicit NativeReader(const fs::path& dir) : dir_(dir) {
    const fs::path manifest = dir / "sequence.json";
    json j = readJson(manifest);
    const std::string where = "'" + manifest.string() + "'";
    try {
      if (!j.is_object() || j.value("format", "") != "rtdenoise-sequence")
        throw Error(where + ": field 'format' must be \"rtdenoise-sequence\"");
      for (const char* key : {"width", "height"})
        if (!j.at(key).is_number_integer()) throw Error(where + ": field '" + key + "' must be an integer");
      const int64_t w = j["width"].get<int64_t>(), h = j["height"].get<int64_t>();
      checkImageSize(where + ": the image", w, h);
      width_ = int(w);
      height_ = int(h);
      if (!j.at("buffers").is_array()) throw Error(where + ": field 'buffers' must be a list of buffer names");
      for (const auto& name : j["buffers"]) {
        auto b = name.is_string() ? bufferFromName(name.get<std::string>()) : std::nullopt;
        if (!b) throw Error(where + ": unknown buffer " + name.dump() + " in field 'buffers'");
        if (std::find(buffers_.begin(), buffers_.end(), *b) != buffers_.end())
          throw Error(where + ": buffer " + name.dump() + " is listed twice in field 'buffers'");
        buffers_.push_back(*b);
      }
      continuous_ = boolField(j, "continuous", where);
      if (j.contains("guideRays")) readGuideRaysField(j["guideRays"], where);
      if (!j.at("frames").is_array()) throw Error(where + ": field 'frames' must be a list");
      for (const auto& f : j["frames"]) {
        if (!f.is_object()) throw Error(where + ": every entry of 'frames' must be an object");
        Entry e;
        e.number = frameNumberFromJson(f.at("number"), where);
        const std::string at = where + ", frame " + std::to_string(e.number);
        if (!frames_.empty() && e.number <= frames_.back().number)
          throw Error(at + (e.number == frames_.back().number ? ": the frame number appears twice"
                                                               : ": frames must be listed in increasing order of number"));
        if (!f.at("file").is_string()) throw Error(at + ": field 'file' must be a file name");
        e.file = f["file"].get<std::string>();
        const fs::path file(e.file);
        if (e.file.empty() || file.is_absolute() || std::find(file.begin(), file.end(), "..") != file.end())
          throw Error(at + ": field 'file' must name a file inside the sequence directory");
        if (f.contains("camera")) {
          e.camera.worldToCamera = matrixFromJson(f["camera"].at("worldToCamera"), at);
          e.camera.projection = matrixFromJson(f["camera"].at("projection"), at);
          e.camera.valid = true;
        }
        e.cut = boolField(f, "cut", at);
        frames_.push_back(e);
      }
    } catch (const json::exception& e) {
      throw Error(where + ": " + e.what());
    }
    if (frames_.empty()) throw Error(where + ": the sequence has no frames");
  }
  SequenceKind kind() const override { return SequenceKind::Native; }
  int frameCount() const override { return int(frames_.size()); }
  int frameNumber(int i) const override {
    checkIndex(i, frameCount(), dir_);
    return frames_[size_t(i)].number;
  }
  fs::path framePath(int i) const override {
    checkIndex(i, frameCount(), dir_);
    return dir_ / frames_[size_t(i)].file;
  }
  int width() const override { return width_; }
  int height() const override { return height_; }
  std::vector<Buffer> buffers() const override { return buffers_; }

  Frame read(int index) const override {
    checkIndex(index, frameCount(), dir_);
    const Entry& e = frames_[size_t(index)];
    const fs::path path = framePath(index);
    const std::string context = "frame " + std::to_string(e.number);
    exr::Header h = exr::readHeader(path);
    if (h.width != width_ || h.height != height_)
      throw Error(context + ", file '" + path.string() + "': size " + std::to_string(h.width) + "x" +
                  std::to_string(h.height) + " differs from the sequence's " + std::to_string(width_) + "x" +
                  std::to_string(height_));
    Frame f;
    f.number = e.number;
    f.width = width_;
    f.height = height_;
    f.camera = e.camera;
    f.cut = cutAt(index);
    // Every buffer in one pass over the file: its chunks hold all channels, so reading buffer
    // by buffer would decompress the whole file once per buffer.
    std::vector<std::string> names;
    for (Buffer b : buffers_)
      for (std::string& n : nativeChannelNames(b)) names.push_back(std::move(n));
    auto planes = exr::readChannels(path, names, context);
    size_t next = 0;
    for (Buffer b : buffers_) {
      const size_t count = size_t(bufferChannelCount(b));
      f[b] = interleave(planes, next, count, width_, height_);
      next += count;
    }
    return f;
  }

  int guideRaySampleCount() const override { return guideSamples_; }
  std::vector<Buffer> guideRaySampleBuffers() const override { return guideSampleBuffers_; }

  GuideRaySamples readGuideRaySamples(int index) const override {
    if (guideSamples_ == 0) return SequenceReader::readGuideRaySamples(index);
    checkIndex(index, frameCount(), dir_);
    const fs::path path = framePath(index);
    const std::string context = "frame " + std::to_string(frames_[size_t(index)].number);
    const std::string where = context + ", file '" + path.string() + "'";
    // One bad value names its channel and pixel.
    auto check = [&](const std::vector<std::string>& names, const std::vector<std::vector<float>>& planes, bool radiance,
                     bool offset) {
      for (size_t c = 0; c < planes.size(); ++c)
        for (size_t i = 0; i < planes[c].size(); ++i) {
          const float v = planes[c][i];
          const char* wrong = !std::isfinite(v)                     ? "not finite"
                              : offset && std::abs(v) > 0.5f         ? "outside [-0.5, 0.5]"
                              : radiance && v < 0.0f                 ? "negative"
                                                                     : nullptr;
          if (wrong)
            throw Error(where + ": channel '" + names[c] + "' at pixel (" + std::to_string(i % size_t(width_)) + ", " +
                        std::to_string(i / size_t(width_)) + ") is " + std::to_string(v) + ", " + wrong);
        }
    };
    // Every sample layer in one pass over the file: per sample its buffers, then its offset.
    std::vector<std::string> names;
    for (int k = 1; k <= guideSamples_; ++k) {
      for (Buffer b : guideSampleBuffers_)
        for (std::string& n : sampleChannelNames(k, b)) names.push_back(std::move(n));
      for (std::string& n : sampleOffsetChannelNames(k)) names.push_back(std::move(n));
    }
    auto planes = exr::readChannels(path, names, context);
    size_t next = 0;
    auto take = [&](size_t count, bool radiance, bool offset) {
      const std::vector<std::string> layerNames(names.begin() + long(next), names.begin() + long(next + count));
      std::vector<std::vector<float>> layer(std::make_move_iterator(planes.begin() + long(next)),
                                            std::make_move_iterator(planes.begin() + long(next + count)));
      next += count;
      check(layerNames, layer, radiance, offset);
      return interleave(layer, width_, height_);
    };
    GuideRaySamples out;
    for (int k = 1; k <= guideSamples_; ++k) {
      Frame sf;
      sf.number = frames_[size_t(index)].number;
      sf.width = width_;
      sf.height = height_;
      for (Buffer b : guideSampleBuffers_) sf[b] = take(size_t(bufferChannelCount(b)), isRadianceBuffer(b), false);
      out.offsets.push_back(take(2, false, true));
      out.samples.push_back(std::move(sf));
    }
    return out;
  }

 protected:
  bool markedCut(int index) const override { return frames_[size_t(index)].cut; }
  bool markedContinuous() const override { return continuous_; }

 private:
  struct Entry {
    int number;
    std::string file;
    Camera camera;
    bool cut = false;
  };
  // sequence.json "guideRays": {"samples": n, "buffers": [...]}.
  void readGuideRaysField(const json& g, const std::string& where) {
    if (!g.is_object()) throw Error(where + ": field 'guideRays' must be an object");
    const json& n = g.at("samples");
    if (!n.is_number_integer() || n.get<int64_t>() < 1 || n.get<int64_t>() > kMaxGuideRaySamples)
      throw Error(where + ": field 'guideRays.samples' must be an integer in [1, " + std::to_string(kMaxGuideRaySamples) +
                  "] (the non-guide samples per pixel, spp - 1)");
    guideSamples_ = int(n.get<int64_t>());
    if (!g.at("buffers").is_array()) throw Error(where + ": field 'guideRays.buffers' must be a list of buffer names");
    for (const auto& name : g["buffers"]) {
      auto b = name.is_string() ? bufferFromName(name.get<std::string>()) : std::nullopt;
      if (!b) throw Error(where + ": unknown buffer " + name.dump() + " in field 'guideRays.buffers'");
      if (std::find(guideSampleBuffers_.begin(), guideSampleBuffers_.end(), *b) != guideSampleBuffers_.end())
        throw Error(where + ": buffer " + name.dump() + " is listed twice in field 'guideRays.buffers'");
      guideSampleBuffers_.push_back(*b);
    }
    const std::string problem = guideSampleBuffersProblem(guideSampleBuffers_, buffers_);
    if (!problem.empty()) throw Error(where + ": field 'guideRays.buffers': " + problem);
  }

  fs::path dir_;
  bool continuous_ = false;
  int width_ = 0, height_ = 0;
  std::vector<Buffer> buffers_;
  int guideSamples_ = 0;
  std::vector<Buffer> guideSampleBuffers_;
  std::vector<Entry> frames_;
};

// ---------------------------------------------------------------------------------------------
// Blender Cycles multilayer EXR (shared/notes/blender-cycles-passes.md; checked on the fixture
// in tests/fixtures/blender by tests/io/blender_test.cpp).

struct BlenderPass {
  Buffer buffer;
  const char* pass;      // pass name after "<layer>."
  const char* channels;  // channel suffixes
};
// In order of preference: the first pass found for a buffer is used.
constexpr BlenderPass kBlenderPasses[] = {
    {Buffer::Color, "Combined", "RGB"},
    {Buffer::Albedo, "Denoising Albedo", "RGB"},
    {Buffer::Albedo, "DiffCol", "RGB"},
    {Buffer::Normal, "Normal", "XYZ"},
    {Buffer::Depth, "Depth", "Z"},
    {Buffer::Position, "Position", "XYZ"},
    {Buffer::Motion, "Vector", "XY"},
    {Buffer::ObjectId, "IndexOB", "X"},
};

// Cycles' light passes (use_pass_diffuse_*, use_pass_glossy_*, use_pass_transmission_*,
// use_pass_emit, use_pass_environment), already demodulated by their colour pass:
//   Combined = (DiffDir + DiffInd) DiffCol + (GlossDir + GlossInd) GlossCol
//            + (TransDir + TransInd) TransCol + Emit + Env.
// With the glossy passes the frame is split into lobes: Specular = (GlossDir + GlossInd)
// GlossCol with SpecularAlbedo = GlossCol, and Diffuse = Combined - Specular (the diffuse
// lobe, transmission, emission and environment: Diffuse + Specular = Color exactly), with
// DiffuseAlbedo = DiffCol; Emission = Emit + Env (the emitters and sky seen directly).
struct BlenderLightPasses {
  bool glossy = false, diffuseColor = false, emit = false, env = false;
  bool any() const { return glossy || diffuseColor || emit || env; }
};

// cameras.json as tools/blender/make_fixture.py writes it: "cameras": {"<frame>":
// {"world_to_camera": 4x4, "projection": 4x4, ...}}, row-major (Blender's matrices); or the
// list form, "cameras": [{"frame": N, ...}, ...] (or the list alone), keyed by each entry's
// "frame". An entry may say "cut": true (history is reset at that frame).
void loadCameraFile(const fs::path& path, std::map<int, Camera>& cameras, std::set<int>& cutFrames) {
  json j = readJson(path);
  const std::string where = "'" + path.string() + "'";
  try {
    const json& cams = j.is_array() ? j : j.at("cameras");
    auto add = [&](int frame, const json& cam) {
      const std::string at = where + ", camera of frame " + std::to_string(frame);
      if (!cam.is_object()) throw Error(at + ": must be an object");
      if (cameras.count(frame)) throw Error(at + ": the frame has two cameras");
      Camera c;
      c.worldToCamera = matrixFromJson(cam.at("world_to_camera"), at);
      c.projection = matrixFromJson(cam.at("projection"), at);
      c.valid = true;
      cameras[frame] = c;
      if (boolField(cam, "cut", at)) cutFrames.insert(frame);
    };
    if (cams.is_array()) {
      for (const auto& cam : cams) {
        if (!cam.is_object() || !cam.contains("frame"))
          throw Error(where + ": every entry of the camera list needs a field 'frame' (the frame number)");
        add(frameNumberFromJson(cam["frame"], where), cam);
      }
    } else if (cams.is_object()) {
      for (const auto& [key, cam] : cams.items()) {
        auto frame = frameNumberFromText(key);
        if (!frame)
          throw Error(where + ": camera key '" + key + "' is not a frame number in [0, " + std::to_string(kMaxFrameNumber) + "]");
        add(*frame, cam);
      }
    } else {
      throw Error(where + ": field 'cameras' must be an object keyed by frame number or a list");
    }
  } catch (const json::exception& e) {
    throw Error(where + ": " + e.what());
  }
}


class BlenderReader final : public SequenceReader {
 public:
  BlenderReader(const fs::path& dir, std::vector<std::pair<int, fs::path>> files, const std::string& layer)
      : dir_(dir), files_(std::move(files)), layer_(layer) {
    exr::Header h = exr::readHeader(files_.front().second);
    width_ = h.width;
    height_ = h.height;
    for (const auto& p : kBlenderPasses) {
      if (std::find(buffers_.begin(), buffers_.end(), p.buffer) != buffers_.end()) continue;
      if (std::find(h.channels.begin(), h.channels.end(), channelName(p, 0)) != h.channels.end()) {
        buffers_.push_back(p.buffer);
        passes_.push_back(&p);
      }
    }
    auto has = [&](const char* pass) {
      return std::find(h.channels.begin(), h.channels.end(), layer_ + "." + pass + ".R") != h.channels.end();
    };
    light_.glossy = has("GlossDir") && has("GlossInd") && has("GlossCol");
    light_.diffuseColor = has("DiffCol");
    light_.emit = has("Emit");
    light_.env = has("Env");
    auto add = [&](Buffer b) {
      if (std::find(buffers_.begin(), buffers_.end(), b) == buffers_.end()) buffers_.push_back(b);
    };
    if (light_.glossy) {
      add(Buffer::Diffuse);
      add(Buffer::Specular);
      add(Buffer::SpecularAlbedo);
      if (light_.diffuseColor) add(Buffer::DiffuseAlbedo);
    }
    if (light_.emit || light_.env) add(Buffer::Emission);
    const fs::path cameras = dir / "cameras.json";
    if (fs::exists(cameras)) loadCameraFile(cameras, cameras_, cutFrames_);
  }
  SequenceKind kind() const override { return SequenceKind::Blender; }
  int frameCount() const override { return int(files_.size()); }
  int frameNumber(int i) const override {
    checkIndex(i, frameCount(), dir_);
    return files_[size_t(i)].first;
  }
  fs::path framePath(int i) const override {
    checkIndex(i, frameCount(), dir_);
    return files_[size_t(i)].second;
  }
  int width() const override { return width_; }
  int height() const override { return height_; }
  std::vector<Buffer> buffers() const override { return buffers_; }

  Frame read(int index) const override {
    checkIndex(index, frameCount(), dir_);
    const auto& [number, path] = files_[size_t(index)];
    const std::string context = "frame " + std::to_string(number);
    exr::Header h = exr::readHeader(path);
    if (h.width != width_ || h.height != height_)
      throw Error(context + ", file '" + path.string() + "': size " + std::to_string(h.width) + "x" +
                  std::to_string(h.height) + " differs from the first frame's " + std::to_string(width_) + "x" +
                  std::to_string(height_));
    Frame f;
    f.number = number;
    f.width = width_;
    f.height = height_;
    // Every pass in one pass over the file (its chunks hold all channels): the buffers' passes,
    // then the light passes (BlenderLightPasses).
    std::vector<std::string> names;
    for (const BlenderPass* p : passes_)
      for (size_t c = 0; p->channels[c]; ++c) names.push_back(channelName(*p, c));
    const size_t lightFirst = names.size();
    const std::vector<std::string> light = lightPasses();
    for (const auto& p : light)
      for (const char* c : {"R", "G", "B"}) names.push_back(layer_ + "." + p + "." + c);
    auto planes = exr::readChannels(path, names, context);
    size_t next = 0;
    for (const BlenderPass* p : passes_) {
      const size_t count = std::char_traits<char>::length(p->channels);
      if (p->buffer == Buffer::Motion) {
        // Blender: previous position = (x + Vector.X, row - Vector.Y), y up; ours is y down.
        for (float& v : planes[next + 1]) v = -v;
      }
      f[p->buffer] = interleave(planes, next, count, width_, height_);
      next += count;
    }
    combineLightPasses(light, planes, lightFirst, f);
    auto cam = cameras_.find(number);
    if (cam != cameras_.end()) f.camera = cam->second;
    f.cut = cutAt(index);
    return f;
  }

 protected:
  bool markedCut(int index) const override { return cutFrames_.count(files_[size_t(index)].first) > 0; }

 private:
  // The light passes the file has (BlenderLightPasses), in the order read.
  std::vector<std::string> lightPasses() const {
    std::vector<std::string> passes;
    if (light_.glossy) passes.insert(passes.end(), {"GlossDir", "GlossInd", "GlossCol"});
    if (light_.glossy && light_.diffuseColor) passes.push_back("DiffCol");
    if (light_.emit) passes.push_back("Emit");
    if (light_.env) passes.push_back("Env");
    return passes;
  }
  // The lobes, their colours and the emission from the light passes `passes`, whose RGB planes
  // start at planes[first].
  void combineLightPasses(const std::vector<std::string>& passes, const std::vector<std::vector<float>>& planes,
                          size_t first, Frame& f) const {
    if (passes.empty()) return;
    auto pass = [&](const std::string& name) {
      const size_t k = first + 3 * size_t(std::find(passes.begin(), passes.end(), name) - passes.begin());
      return std::vector<std::vector<float>>(planes.begin() + long(k), planes.begin() + long(k) + 3);
    };
    const size_t n = size_t(width_) * height_;
    if (light_.glossy) {
      const auto dir = pass("GlossDir"), ind = pass("GlossInd"), col = pass("GlossCol");
      std::vector<std::vector<float>> specular(3, std::vector<float>(n)), diffuse(3, std::vector<float>(n));
      const Image& combined = f[Buffer::Color];
      for (int c = 0; c < 3; ++c)
        for (size_t i = 0; i < n; ++i) {
          specular[c][i] = (dir[c][i] + ind[c][i]) * col[c][i];
          diffuse[c][i] = combined.pixels[i * combined.channels + c] - specular[c][i];
        }
      f[Buffer::Specular] = interleave(specular, width_, height_);
      f[Buffer::Diffuse] = interleave(diffuse, width_, height_);
      f[Buffer::SpecularAlbedo] = interleave(col, width_, height_);
      if (light_.diffuseColor) f[Buffer::DiffuseAlbedo] = interleave(pass("DiffCol"), width_, height_);
    }
    if (light_.emit || light_.env) {
      std::vector<std::vector<float>> e(3, std::vector<float>(n, 0.0f));
      for (const auto& [name, present] : {std::pair{"Emit", light_.emit}, std::pair{"Env", light_.env}}) {
        if (!present) continue;
        const auto p = pass(name);
        for (int c = 0; c < 3; ++c)
          for (size_t i = 0; i < n; ++i) e[c][i] += p[c][i];
      }
      f[Buffer::Emission] = interleave(e, width_, height_);
    }
  }

  std::string channelName(const BlenderPass& p, size_t c) const {
    return layer_ + "." + p.pass + "." + std::string(1, p.channels[c]);
  }
  fs::path dir_;
  std::vector<std::pair<int, fs::path>> files_;
  std::string layer_;
  int width_ = 0, height_ = 0;
  std::vector<Buffer> buffers_;
  std::vector<const BlenderPass*> passes_;
  BlenderLightPasses light_;
  std::map<int, Camera> cameras_;
  std::set<int> cutFrames_;
};

// ---------------------------------------------------------------------------------------------
// Per-buffer image files: <buffer>_<number>.<ext> (color_0001.exr, albedo_0001.pfm, ...), one
// file per buffer per frame, any format readImageFile() reads (docs/sequence-format.md).

/// A per-buffer file name: a buffer's canonical name (any case), an optional '_', '.' or '-',
/// the frame number, and an image extension.
std::optional<std::pair<Buffer, int>> perBufferFile(const fs::path& p) {
  static const std::regex pattern(R"(^([A-Za-z]+)[_.-]?(\d+)\.(exr|pfm|hdr|png|tif|tiff)$)", std::regex::icase);
  std::smatch m;
  const std::string name = p.filename().string();
  if (!std::regex_match(name, m, pattern)) return std::nullopt;
  std::string stem = m[1].str();
  std::transform(stem.begin(), stem.end(), stem.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
  for (int b = 0; b < kBufferCount; ++b) {
    std::string canonical(bufferName(Buffer(b)));
    std::transform(canonical.begin(), canonical.end(), canonical.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
    if (canonical != stem) continue;
    auto n = frameNumberFromText(m[2].str());
    if (!n)
      throw Error("file '" + p.string() + "': frame number " + m[2].str() + " is out of range [0, " +
                  std::to_string(kMaxFrameNumber) + "]");
    return std::pair{Buffer(b), *n};
  }
  return std::nullopt;
}

/// The buffer `b` from one file's pixels. Channels: the first bufferChannelCount(b) of the
/// file's; a single-channel file fills an RGB buffer (a grey albedo). Integer files (PNG,
/// 8/16-bit TIFF) hold display values: RGB buffers are sRGB-decoded when the file says sRGB,
/// normals map [0, 1] to [-1, 1]; other buffers need a floating-point file.
Image bufferFromFile(const io::ImageFile& file, Buffer b, const fs::path& path, const std::string& context) {
  const std::string where = context + ", buffer '" + std::string(bufferName(b)) + "', file '" + path.string() + "'";
  const std::string_view layout = bufferChannels(b);
  const int n = int(layout.size()), c = file.image.channels;
  if (c < n && !(c == 1 && layout == "RGB"))
    throw Error(where + ": " + std::to_string(c) + " channel(s), the buffer needs " + std::to_string(n));
  const bool normalLike = b == Buffer::Normal || b == Buffer::ReflectedNormal || b == Buffer::MirrorDirection;
  if (file.integer && layout != "RGB" && !normalLike)
    throw Error(where + ": an integer image (PNG or 8/16-bit TIFF) cannot hold " + std::string(bufferName(b)) +
                "; use a floating-point format (EXR, PFM, HDR or float TIFF)");
  Image out(file.image.width, file.image.height, n);
  const size_t pixels = size_t(out.width) * out.height;
  for (size_t i = 0; i < pixels; ++i)
    for (int k = 0; k < n; ++k) {
      float v = file.image.pixels[i * size_t(c) + size_t(c == 1 ? 0 : k)];
      if (file.integer) v = layout == "RGB" ? (file.srgb ? tonemap::srgbDecode(v) : v) : 2.0f * v - 1.0f;
      out.pixels[i * size_t(n) + size_t(k)] = v;
    }
  return out;
}

class PerBufferReader final : public SequenceReader {
 public:
  /// `files`: every per-buffer file of the directory (perBufferFile()), with its buffer and number.
  PerBufferReader(const fs::path& dir, const std::vector<std::tuple<Buffer, int, fs::path>>& files) : dir_(dir) {
    std::map<int, std::map<Buffer, fs::path>> byFrame;
    std::set<Buffer> present;
    for (const auto& [b, number, path] : files) {
      auto [it, fresh] = byFrame[number].emplace(b, path);
      if (!fresh)
        throw Error("input '" + dir.string() + "': files '" + it->second.filename().string() + "' and '" +
                    path.filename().string() + "' are both buffer '" + std::string(bufferName(b)) + "' of frame " +
                    std::to_string(number));
      present.insert(b);
    }
    if (!present.count(Buffer::Color))
      throw Error("input '" + dir.string() + "': per-buffer files but no color_<number> file (e.g. color_0001.exr)");
    buffers_.assign(present.begin(), present.end());
    for (auto& [number, buffers] : byFrame) {
      for (Buffer b : buffers_)
        if (!buffers.count(b))
          throw Error("input '" + dir.string() + "', frame " + std::to_string(number) + ": no file for buffer '" +
                      std::string(bufferName(b)) + "', which other frames have (e.g. " +
                      std::string(bufferName(b)) + "_" + std::to_string(number) + ".exr)");
      frames_.push_back({number, std::move(buffers)});
    }
    const io::ImageFile first = io::readImageFile(frames_.front().files.at(Buffer::Color), "frame " + std::to_string(frames_.front().number));
    width_ = first.image.width;
    height_ = first.image.height;
    const fs::path cameras = dir / "cameras.json";
    if (fs::exists(cameras)) loadCameraFile(cameras, cameras_, cutFrames_);
  }
  SequenceKind kind() const override { return SequenceKind::PerBuffer; }
  int frameCount() const override { return int(frames_.size()); }
  int frameNumber(int i) const override {
    checkIndex(i, frameCount(), dir_);
    return frames_[size_t(i)].number;
  }
  fs::path framePath(int i) const override {
    checkIndex(i, frameCount(), dir_);
    return frames_[size_t(i)].files.at(Buffer::Color);
  }
  int width() const override { return width_; }
  int height() const override { return height_; }
  std::vector<Buffer> buffers() const override { return buffers_; }

  Frame read(int index) const override {
    checkIndex(index, frameCount(), dir_);
    const Entry& e = frames_[size_t(index)];
    const std::string context = "frame " + std::to_string(e.number);
    Frame f;
    f.number = e.number;
    f.width = width_;
    f.height = height_;
    for (const auto& [b, path] : e.files) {
      const io::ImageFile file = io::readImageFile(path, context);
      if (file.image.width != width_ || file.image.height != height_)
        throw Error(context + ", buffer '" + std::string(bufferName(b)) + "', file '" + path.string() + "': size " +
                    std::to_string(file.image.width) + "x" + std::to_string(file.image.height) +
                    " differs from the first colour file's " + std::to_string(width_) + "x" + std::to_string(height_));
      f[b] = bufferFromFile(file, b, path, context);
    }
    auto cam = cameras_.find(e.number);
    if (cam != cameras_.end()) f.camera = cam->second;
    f.cut = cutAt(index);
    return f;
  }

 protected:
  bool markedCut(int index) const override { return cutFrames_.count(frames_[size_t(index)].number) > 0; }

 private:
  struct Entry {
    int number;
    std::map<Buffer, fs::path> files;
  };
  fs::path dir_;
  int width_ = 0, height_ = 0;
  std::vector<Buffer> buffers_;
  std::vector<Entry> frames_;
  std::map<int, Camera> cameras_;
  std::set<int> cutFrames_;
};

}  // namespace

std::string_view sequenceKindName(SequenceKind kind) {
  switch (kind) {
    case SequenceKind::Native: return "native";
    case SequenceKind::PerBuffer: return "per-buffer";
    case SequenceKind::Blender: return "blender";
  }
  return "?";
}

std::unique_ptr<SequenceReader> SequenceReader::open(const fs::path& dir, const SequenceOptions& options) {
  auto reader = openKind(dir);
  reader->options_ = options;
  return reader;
}

std::unique_ptr<SequenceReader> SequenceReader::openKind(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw Error("input '" + dir.string() + "' is not a directory");
  if (fs::exists(dir / "sequence.json", ec)) return std::make_unique<NativeReader>(dir);
  std::vector<std::pair<int, fs::path>> files;
  std::vector<std::tuple<Buffer, int, fs::path>> perBuffer;
  fs::directory_iterator it(dir, ec);
  if (ec) throw Error("input '" + dir.string() + "': cannot list the directory (" + ec.message() + ")");
  for (const auto& entry : it) {
    if (auto pb = perBufferFile(entry.path())) {
      perBuffer.emplace_back(pb->first, pb->second, entry.path());
      continue;
    }
    if (entry.path().extension() != ".exr") continue;
    auto n = frameNumberOf(entry.path());
    if (n) files.emplace_back(*n, entry.path());
  }
  if (!perBuffer.empty()) return std::make_unique<PerBufferReader>(dir, perBuffer);
  if (files.empty())
    throw Error("input '" + dir.string() + "' has neither sequence.json (native format), per-buffer files "
                "(color_0001.exr, albedo_0001.pfm, ...) nor numbered .exr frames (Blender)");
  std::sort(files.begin(), files.end());
  for (size_t i = 1; i < files.size(); ++i)
    if (files[i].first == files[i - 1].first)
      throw Error("input '" + dir.string() + "': files '" + files[i - 1].second.filename().string() + "' and '" +
                  files[i].second.filename().string() + "' have the same frame number");
  exr::Header h = exr::readHeader(files.front().second);
  const std::string suffix = ".Combined.R";
  for (const auto& c : h.channels)
    if (c.size() > suffix.size() && c.compare(c.size() - suffix.size(), suffix.size(), suffix) == 0)
      return std::make_unique<BlenderReader>(dir, std::move(files), c.substr(0, c.size() - suffix.size()));
  throw Error("file '" + files.front().second.string() +
              "' has no '<layer>.Combined.R' channel: not a Blender multilayer EXR, and there is no sequence.json");
}

// ---------------------------------------------------------------------------------------------
// Writer

SequenceWriter::SequenceWriter(fs::path dir) : dir_(std::move(dir)) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec) throw Error("cannot create the output directory '" + dir_.string() + "': " + ec.message());
  removeStaleTemporaryFiles(dir_);
}

static std::string frameFileName(int number) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04d.exr", number);
  return name;
}

void SequenceWriter::write(const Frame& frame, const GuideRaySamples* samples) {
  if (frame.number < 0)
    throw Error("frame " + std::to_string(frame.number) + ": frame numbers must lie in [0, " + std::to_string(kMaxFrameNumber) + "]");
  for (const Written& w : frames_)
    if (w.number == frame.number)
      throw Error("frame " + std::to_string(frame.number) + " was already written to '" + dir_.string() + "'");
  std::vector<Buffer> present;
  for (int i = 0; i < kBufferCount; ++i)
    if (frame.has(Buffer(i))) present.push_back(Buffer(i));
  if (frames_.empty()) {
    width_ = frame.width;
    height_ = frame.height;
    buffers_ = present;
  } else if (frame.width != width_ || frame.height != height_ || present != buffers_) {
    throw Error("frame " + std::to_string(frame.number) + " differs in size or buffers from the first frame written");
  }
  std::vector<exr::ChannelSource> channels;
  for (Buffer b : present) {
    const Image& img = frame[b];
    auto names = nativeChannelNames(b);
    if (img.channels != int(names.size()) || img.width != frame.width || img.height != frame.height)
      throw Error("frame " + std::to_string(frame.number) + ": buffer '" + std::string(bufferName(b)) + "' has the wrong shape");
    for (size_t c = 0; c < names.size(); ++c) channels.push_back({names[c], img.pixels.data() + c, size_t(img.channels)});
  }
  // Guide-ray samples: the same count and buffers in every frame, checked as the reader does.
  const int n = samples ? int(samples->samples.size()) : 0;
  std::vector<Buffer> sampleBuffers;
  if (n > 0)
    for (int i = 0; i < kBufferCount; ++i)
      if (samples->samples[0].has(Buffer(i))) sampleBuffers.push_back(Buffer(i));
  const std::string at = "frame " + std::to_string(frame.number) + ": ";
  if (n > 0 && samples->offsets.size() != size_t(n))
    throw Error(at + std::to_string(n) + " guide-ray samples but " + std::to_string(samples->offsets.size()) + " offset images");
  if (frames_.empty()) {
    if (n > kMaxGuideRaySamples)
      throw Error(at + std::to_string(n) + " guide-ray samples per pixel, at most " + std::to_string(kMaxGuideRaySamples));
    const std::string problem = n > 0 ? guideSampleBuffersProblem(sampleBuffers, present) : "";
    if (!problem.empty()) throw Error(at + "guide-ray samples: " + problem);
    guideSamples_ = n;
    guideSampleBuffers_ = sampleBuffers;
  } else if (n != guideSamples_ || sampleBuffers != guideSampleBuffers_) {
    throw Error(at + std::to_string(n) + " guide-ray samples (or their buffers) differ from the first frame written's " +
                std::to_string(guideSamples_));
  }
  for (int k = 1; k <= n; ++k) {
    const Frame& sf = samples->samples[size_t(k - 1)];
    const Image& off = samples->offsets[size_t(k - 1)];
    std::vector<std::pair<std::vector<std::string>, const Image*>> layers;
    for (int i = 0; i < kBufferCount; ++i)
      if (sf.has(Buffer(i)) != (std::find(sampleBuffers.begin(), sampleBuffers.end(), Buffer(i)) != sampleBuffers.end()))
        throw Error(at + "guide-ray sample " + std::to_string(k) + " differs in buffers from sample 1 ('" +
                    std::string(bufferName(Buffer(i))) + "')");
    for (Buffer b : sampleBuffers) layers.push_back({sampleChannelNames(k, b), &sf[b]});
    layers.push_back({sampleOffsetChannelNames(k), &off});
    for (const auto& [names, img] : layers) {
      if (img->channels != int(names.size()) || img->width != frame.width || img->height != frame.height)
        throw Error(at + "guide-ray layer '" + names[0].substr(0, names[0].rfind('.')) + "' has the wrong shape");
      for (size_t c = 0; c < names.size(); ++c) channels.push_back({names[c], img->pixels.data() + c, size_t(img->channels)});
    }
  }
  exr::writeChannels(dir_ / frameFileName(frame.number), frame.width, frame.height, channels);
  frames_.push_back({frame.number, frame.camera, frame.cut});
}

void SequenceWriter::finish() const {
  json j;
  j["format"] = "rtdenoise-sequence";
  j["version"] = 1;
  j["width"] = width_;
  j["height"] = height_;
  j["conventions"] = {
      {"radiance", "linear, scene-referred RGB"},
      {"normal", "world space, unit length"},
      {"depth", "linear view depth (-z in camera space)"},
      {"motion", "pixels; previous position of pixel centre (x+0.5, y+0.5) is (x+0.5+X, y+0.5+Y), y down"},
      {"matrices", "row-major, column vectors; worldToCamera looks down -Z; projection to OpenGL clip space"},
      {"rows", "row 0 is the top of the image"}};
  json names = json::array();
  for (Buffer b : buffers_) names.push_back(std::string(bufferName(b)));
  j["buffers"] = names;
  if (guideSamples_ > 0) {
    json sampleNames = json::array();
    for (Buffer b : guideSampleBuffers_) sampleNames.push_back(std::string(bufferName(b)));
    j["guideRays"] = {{"samples", guideSamples_}, {"buffers", sampleNames}};
  }
  json frames = json::array();
  std::vector<Written> sorted = frames_;
  std::sort(sorted.begin(), sorted.end(), [](const Written& a, const Written& b) { return a.number < b.number; });
  for (const Written& w : sorted) {
    json f = {{"number", w.number}, {"file", frameFileName(w.number)}};
    if (w.camera.valid) f["camera"] = {{"worldToCamera", w.camera.worldToCamera}, {"projection", w.camera.projection}};
    if (w.cut) f["cut"] = true;
    frames.push_back(f);
  }
  j["frames"] = frames;
  writeFileAtomic(dir_ / "sequence.json", j.dump(1));
}

void writeRgbExr(const fs::path& path, const Image& rgb, ExrPixels pixels) {
  if (rgb.channels < 3) throw Error("cannot write '" + path.string() + "': the image has fewer than 3 channels");
  const size_t s = size_t(rgb.channels);
  exr::writeChannels(path, rgb.width, rgb.height,
                     {{"R", rgb.pixels.data(), s}, {"G", rgb.pixels.data() + 1, s}, {"B", rgb.pixels.data() + 2, s}},
                     pixels == ExrPixels::Half);
}

void setExrThreads(int threads) { exr::setThreads(threads); }

Image readRgbExr(const fs::path& path) {
  exr::Header h = exr::readHeader(path);
  return interleave(exr::readChannels(path, {"R", "G", "B"}, ""), h.width, h.height);
}

}  // namespace rtd
