#include "io/exr.h"

#include <Iex.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfThreading.h>
#include <unistd.h>
#include <Imath/half.h>

#include <algorithm>
#include <fstream>

#include "io/exr_limits.h"
#include "io/temp_files.h"
#include "rtd/error.h"

namespace rtd::exr {

namespace fs = std::filesystem;

static std::string quoted(const fs::path& p) {
  std::string s = "'";  // appended, not "'" + ...: GCC 12 warns falsely (-Wrestrict) on that form
  s += p.string();
  s += '\'';
  return s;
}

Header readHeader(const fs::path& path) {
  checkHeader(path);
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i dw = file.header().dataWindow();
    Header h;
    h.width = dw.max.x - dw.min.x + 1;
    h.height = dw.max.y - dw.min.y + 1;
    for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it)
      h.channels.emplace_back(it.name());
    return h;
  } catch (const std::exception& e) {
    throw Error("file " + quoted(path) + " is not a readable EXR: " + e.what());
  }
}

std::vector<std::vector<float>> readChannels(const fs::path& path, const std::vector<std::string>& names,
                                             const std::string& context) {
  const std::string where = (context.empty() ? "" : context + ", ") + "file " + quoted(path);
  const ReadDeadline deadline(where);
  HeaderCheck checked;
  try {
    checked = checkHeader(path);
  } catch (const Error& e) {
    throw Error((context.empty() ? "" : context + ", ") + e.what());
  }
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i dw = file.header().dataWindow();
    const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
    if (w != checked.width || h != checked.height) throw Error(where + ": the header does not parse consistently");
    std::vector<std::vector<float>> planes(names.size(), std::vector<float>(size_t(w) * h));
    // All channels in one frame buffer, so one pass over the file decodes each chunk once. A
    // name asked for twice is read once and copied (a frame buffer holds one slice per name).
    std::vector<std::pair<size_t, size_t>> repeats;  // (copy, of)
    Imf::FrameBuffer fb;
    for (size_t i = 0; i < names.size(); ++i) {
      if (!file.header().channels().findChannel(names[i]))
        throw Error(where + ": missing channel '" + names[i] + "'");
      const size_t first = size_t(std::find(names.begin(), names.end(), names[i]) - names.begin());
      if (first != i) {
        repeats.emplace_back(i, first);
        continue;
      }
      fb.insert(names[i], Imf::Slice::Make(Imf::FLOAT, planes[i].data(), dw, sizeof(float), sizeof(float) * size_t(w)));
    }
    file.setFrameBuffer(fb);
    try {
      // Slab by slab (whole chunks), so that a file whose decoding stalls stops at the deadline;
      // a slab has a few chunks per thread of OpenEXR's pool (setExrThreads) to decode in parallel.
      const int chunks = std::max(1, 32 / checked.linesPerChunk) * std::max(1, Imf::globalThreadCount());
      const int slab = checked.linesPerChunk * chunks;
      for (int y = dw.min.y; y <= dw.max.y; y += slab) {
        deadline.check();
        file.readPixels(y, std::min(dw.max.y, y + slab - 1));
      }
    } catch (const Error&) {
      throw;
    } catch (const std::exception& e) {
      std::string list;
      for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
      throw Error(where + ": pixel data of channels " + list + " is truncated or corrupt (" + e.what() + ")");
    }
    for (const auto& [copy, of] : repeats) planes[copy] = planes[of];
    return planes;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(where + ": not a readable EXR (" + e.what() + ")");
  }
}

void setThreads(int threads) {
  if (threads < 0 || threads > 4096)
    throw Error("EXR threads: " + std::to_string(threads) + ", expected 0 (the calling thread) to 4096");
  Imf::setGlobalThreadCount(threads);
}

void writeChannels(const fs::path& path, int width, int height, const std::vector<ChannelSource>& channels, bool half) {
  TemporaryFile tmp(path);
  try {
    Imf::Header header(width, height);
    header.compression() = Imf::ZIP_COMPRESSION;
    Imf::FrameBuffer fb;
    // OpenEXR writes a slice only as its own pixel type: half channels get half copies.
    std::vector<std::vector<Imath::half>> halves(half ? channels.size() : 0);
    for (size_t k = 0; k < channels.size(); ++k) {
      const auto& c = channels[k];
      header.channels().insert(c.name, Imf::Channel(half ? Imf::HALF : Imf::FLOAT));
      if (half) {
        auto& h = halves[k];
        h.resize(size_t(width) * height);
        for (size_t i = 0; i < h.size(); ++i) h[i] = Imath::half(c.data[i * c.stride]);
        fb.insert(c.name, Imf::Slice(Imf::HALF, (char*)h.data(), sizeof(Imath::half), sizeof(Imath::half) * size_t(width)));
      } else {
        fb.insert(c.name, Imf::Slice(Imf::FLOAT, (char*)c.data, sizeof(float) * c.stride,
                                     sizeof(float) * c.stride * size_t(width)));
      }
    }
    {
      Imf::OutputFile out(tmp.path().c_str(), header);
      out.setFrameBuffer(fb);
      out.writePixels(height);
    }
    tmp.commit();
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error("cannot write " + quoted(path) + ": " + e.what());
  }
}

}  // namespace rtd::exr
