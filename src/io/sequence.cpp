// Native and Blender sequence readers, the native writer, and RGB EXR helpers.
#include "rtd/sequence.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <nlohmann/json.hpp>
#include <map>
#include <regex>
#include <sstream>

#include "io/exr.h"
#include "rtd/error.h"

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
  return in;
}

/// EXR channel names of a buffer in the native format: "<name>.<C>", "id" for id channels.
static std::vector<std::string> nativeChannelNames(Buffer b) {
  std::vector<std::string> names;
  for (char c : bufferChannels(b))
    names.push_back(std::string(bufferName(b)) + "." + (c == 'I' ? std::string("id") : std::string(1, c)));
  return names;
}

static Image interleave(const std::vector<std::vector<float>>& planes, int w, int h) {
  Image img(w, h, int(planes.size()));
  for (size_t c = 0; c < planes.size(); ++c)
    for (size_t i = 0; i < size_t(w) * h; ++i) img.pixels[i * planes.size() + c] = planes[c][i];
  return img;
}

static std::array<float, 16> matrixFromJson(const json& j, const std::string& where) {
  std::array<float, 16> m{};
  std::vector<float> flat;
  if (j.is_array() && j.size() == 4 && j[0].is_array()) {
    for (const auto& row : j)
      for (const auto& v : row) flat.push_back(v.get<float>());
  } else if (j.is_array()) {
    for (const auto& v : j) flat.push_back(v.get<float>());
  }
  if (flat.size() != 16) throw Error(where + ": a camera matrix needs 16 numbers");
  std::copy(flat.begin(), flat.end(), m.begin());
  return m;
}

static json readJson(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw Error("cannot open '" + path.string() + "'");
  try {
    return json::parse(in);
  } catch (const std::exception& e) {
    throw Error("'" + path.string() + "' is not valid JSON: " + e.what());
  }
}

void writeFileAtomic(const fs::path& path, const std::string& data) {
  const fs::path tmp = path.string() + ".tmp" + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary);
    out << data;
    out.flush();
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw Error("cannot write '" + path.string() + "'");
    }
  }
  fs::rename(tmp, path);
}

/// Frame number from a file name: the last run of digits (frame_0012.exr -> 12).
static std::optional<int> frameNumberOf(const fs::path& p) {
  static const std::regex digits("(\\d+)(?!.*\\d)");
  std::smatch m;
  std::string stem = p.stem().string();
  if (!std::regex_search(stem, m, digits)) return std::nullopt;
  return std::stoi(m[1]);
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
      if (j.value("format", "") != "rtdenoise-sequence") throw Error(where + ": field 'format' must be \"rtdenoise-sequence\"");
      width_ = j.at("width").get<int>();
      height_ = j.at("height").get<int>();
      for (const auto& name : j.at("buffers")) {
        auto b = bufferFromName(name.get<std::string>());
        if (!b) throw Error(where + ": unknown buffer '" + name.get<std::string>() + "' in field 'buffers'");
        buffers_.push_back(*b);
      }
      for (const auto& f : j.at("frames")) {
        Entry e;
        e.number = f.at("number").get<int>();
        e.file = f.at("file").get<std::string>();
        if (f.contains("camera")) {
          e.camera.worldToCamera = matrixFromJson(f["camera"].at("worldToCamera"), where);
          e.camera.projection = matrixFromJson(f["camera"].at("projection"), where);
          e.camera.valid = true;
        }
        frames_.push_back(e);
      }
    } catch (const json::exception& e) {
      throw Error(where + ": " + e.what());
    }
    if (frames_.empty()) throw Error(where + ": the sequence has no frames");
  }
  SequenceKind kind() const override { return SequenceKind::Native; }
  int frameCount() const override { return int(frames_.size()); }
  int frameNumber(int i) const override { return frames_.at(i).number; }
  fs::path framePath(int i) const override { return dir_ / frames_.at(i).file; }
  int width() const override { return width_; }
  int height() const override { return height_; }
  std::vector<Buffer> buffers() const override { return buffers_; }

  Frame read(int index) const override {
    const Entry& e = frames_.at(index);
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
    for (Buffer b : buffers_)
      f[b] = interleave(exr::readChannels(path, nativeChannelNames(b), context), width_, height_);
    return f;
  }

 private:
  struct Entry {
    int number;
    std::string file;
    Camera camera;
  };
  fs::path dir_;
  int width_ = 0, height_ = 0;
  std::vector<Buffer> buffers_;
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
    const fs::path cameras = dir / "cameras.json";
    if (fs::exists(cameras)) loadCameras(cameras);
  }
  SequenceKind kind() const override { return SequenceKind::Blender; }
  int frameCount() const override { return int(files_.size()); }
  int frameNumber(int i) const override { return files_.at(i).first; }
  fs::path framePath(int i) const override { return files_.at(i).second; }
  int width() const override { return width_; }
  int height() const override { return height_; }
  std::vector<Buffer> buffers() const override { return buffers_; }

  Frame read(int index) const override {
    const auto& [number, path] = files_.at(index);
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
    for (const BlenderPass* p : passes_) {
      std::vector<std::string> names;
      for (size_t c = 0; p->channels[c]; ++c) names.push_back(channelName(*p, c));
      auto planes = exr::readChannels(path, names, context);
      if (p->buffer == Buffer::Motion) {
        // Blender: previous position = (x + Vector.X, row - Vector.Y), y up; ours is y down.
        for (float& v : planes[1]) v = -v;
      }
      f[p->buffer] = interleave(planes, width_, height_);
    }
    auto cam = cameras_.find(number);
    if (cam != cameras_.end()) f.camera = cam->second;
    return f;
  }

 private:
  std::string channelName(const BlenderPass& p, size_t c) const {
    return layer_ + "." + p.pass + "." + std::string(1, p.channels[c]);
  }
  // cameras.json as tools/blender/make_fixture.py writes it: "cameras": {"<frame>":
  // {"world_to_camera": 4x4, "projection": 4x4, ...}}, row-major (Blender's matrices).
  void loadCameras(const fs::path& path) {
    json j = readJson(path);
    const std::string where = "'" + path.string() + "'";
    try {
      for (const auto& [frame, cam] : j.at("cameras").items()) {
        Camera c;
        c.worldToCamera = matrixFromJson(cam.at("world_to_camera"), where);
        c.projection = matrixFromJson(cam.at("projection"), where);
        c.valid = true;
        cameras_[std::stoi(frame)] = c;
      }
    } catch (const json::exception& e) {
      throw Error(where + ": " + e.what());
    }
  }

  fs::path dir_;
  std::vector<std::pair<int, fs::path>> files_;
  std::string layer_;
  int width_ = 0, height_ = 0;
  std::vector<Buffer> buffers_;
  std::vector<const BlenderPass*> passes_;
  std::map<int, Camera> cameras_;
};

}  // namespace

std::unique_ptr<SequenceReader> SequenceReader::open(const fs::path& dir) {
  if (!fs::is_directory(dir)) throw Error("input '" + dir.string() + "' is not a directory");
  if (fs::exists(dir / "sequence.json")) return std::make_unique<NativeReader>(dir);
  std::vector<std::pair<int, fs::path>> files;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() != ".exr") continue;
    auto n = frameNumberOf(entry.path());
    if (n) files.emplace_back(*n, entry.path());
  }
  if (files.empty())
    throw Error("input '" + dir.string() + "' has neither sequence.json (native format) nor numbered .exr frames (Blender)");
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

SequenceWriter::SequenceWriter(fs::path dir) : dir_(std::move(dir)) { fs::create_directories(dir_); }

static std::string frameFileName(int number) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04d.exr", number);
  return name;
}

void SequenceWriter::write(const Frame& frame) {
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
  exr::writeChannels(dir_ / frameFileName(frame.number), frame.width, frame.height, channels);
  frames_.emplace_back(frame.number, frame.camera);
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
  json frames = json::array();
  for (const auto& [number, cam] : frames_) {
    json f = {{"number", number}, {"file", frameFileName(number)}};
    if (cam.valid) f["camera"] = {{"worldToCamera", cam.worldToCamera}, {"projection", cam.projection}};
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

Image readRgbExr(const fs::path& path) {
  exr::Header h = exr::readHeader(path);
  return interleave(exr::readChannels(path, {"R", "G", "B"}, ""), h.width, h.height);
}

}  // namespace rtd
