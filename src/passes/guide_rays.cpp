// Supersampling with guide rays (Voorhuis 2018, Sec. 5): the assignment of non-guide samples to
// guide rays, the Eq. 7 pre-mix and the post-filter copy. include/rtd/guide_rays.h.
#include "rtd/guide_rays.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "core/frame_data.h"
#include "core/parallel.h"
#include "rtd/error.h"

#if defined(RTD_HAS_VULKAN)
#include "backend/vulkan/guide_rays_vulkan.h"
#else
namespace rtd::detail {
struct GuideRaysGpu {};
}  // namespace rtd::detail
#endif

namespace rtd {

namespace {

void checkSize(const Image& img, int w, int h, int channels, const std::string& what) {
  if (img.width != w || img.height != h || img.channels != channels)
    throw Error("guide rays: " + what + " is " + std::to_string(img.width) + "x" + std::to_string(img.height) +
                "x" + std::to_string(img.channels) + ", the guides " + std::to_string(w) + "x" + std::to_string(h) +
                "x" + std::to_string(channels));
}

// What premix() and denoise() accept: the guides' Color, Depth and Normal, and per sample the
// same radiance buffers, Depth, Normal and offsets, all of the guides' size.
void validate(const Frame& guides, const GuideRaySamples& s) {
  const int w = guides.width, h = guides.height;
  for (Buffer b : {Buffer::Color, Buffer::Depth, Buffer::Normal}) {
    if (!guides.has(b)) throw Error("guide rays: the guide frame has no '" + std::string(bufferName(b)) + "' buffer");
    checkSize(guides[b], w, h, bufferChannelCount(b), "the guide frame's " + std::string(bufferName(b)));
  }
  if (s.offsets.size() != s.samples.size())
    throw Error("guide rays: " + std::to_string(s.samples.size()) + " samples but " + std::to_string(s.offsets.size()) +
                " offset images");
  for (int i = 0; i < kBufferCount; ++i)
    if (isRadianceBuffer(Buffer(i)) && guides.has(Buffer(i)))
      checkSize(guides[Buffer(i)], w, h, 3, "the guide frame's " + std::string(bufferName(Buffer(i))));
  const size_t n = s.samples.size();
  for (size_t k = 0; k < n; ++k) {
    const std::string name = "sample " + std::to_string(k + 1);
    for (Buffer b : {Buffer::Color, Buffer::Depth, Buffer::Normal}) {
      if (!s.samples[k].has(b)) throw Error("guide rays: " + name + " has no '" + std::string(bufferName(b)) + "' buffer");
      checkSize(s.samples[k][b], w, h, bufferChannelCount(b), name + " " + std::string(bufferName(b)));
    }
    checkSize(s.offsets[k], w, h, 2, name + " offsets");
    for (size_t i = 0; i < s.offsets[k].pixels.size(); ++i)
      if (!(std::abs(s.offsets[k].pixels[i]) <= 0.5f))
        throw Error("guide rays: " + name + " offset " + (i % 2 ? "Y" : "X") + " at pixel (" +
                    std::to_string(i / 2 % size_t(w)) + ", " + std::to_string(i / 2 / size_t(w)) + ") is " +
                    std::to_string(s.offsets[k].pixels[i]) + ", not in [-0.5, 0.5]");
    // Every radiance buffer is mixed or none: a guide whose colour were mixed but not its
    // lobes would no longer be their sum.
    for (int i = 0; i < kBufferCount; ++i) {
      const Buffer b = Buffer(i);
      if (!isRadianceBuffer(b)) continue;
      if (guides.has(b) != s.samples[k].has(b))
        throw Error("guide rays: " + (guides.has(b) ? name + " has no '" : "the guide frame has no '") +
                    std::string(bufferName(b)) + "' buffer" +
                    (guides.has(b) ? ", which the guide frame has" : ", which " + name + " has"));
      if (guides.has(b)) checkSize(s.samples[k][b], w, h, 3, name + " " + std::string(bufferName(b)));
    }
  }
}

}  // namespace

GuideRays::GuideRays() = default;
GuideRays::~GuideRays() = default;
GuideRays::GuideRays(GuideRays&&) noexcept = default;
GuideRays& GuideRays::operator=(GuideRays&&) noexcept = default;

Frame GuideRays::premix(const Frame& guides, const GuideRaySamples& s, const GuideRaySettings& settings) {
  validate(guides, s);
  const int w = guides.width, h = guides.height;
  const size_t n = s.samples.size();
  width_ = w;
  height_ = h;
  assign_.assign(n, std::vector<int>(size_t(w) * h));
  count_.assign(size_t(w) * h, 1);

  // Assignment (Sec. 5): the sample at (x + 0.5 + ox, y + 0.5 + oy) lies in the cell of the four
  // pixel centres around it; it joins the most similar of those guides inside the image.
  const Image& gz = guides[Buffer::Depth];
  const Image& gn = guides[Buffer::Normal];
  for (size_t k = 0; k < n; ++k) {
    const Image& sz = s.samples[k][Buffer::Depth];
    const Image& sn = s.samples[k][Buffer::Normal];
    const Image& off = s.offsets[k];
    std::vector<int>& a = assign_[k];
    parallelRows(h, [&](int y) {
      for (int x = 0; x < w; ++x) {
        const float px = float(x) + off.at(x, y, 0);
        const float py = float(y) + off.at(x, y, 1);
        const int x0 = int(std::floor(px)), y0 = int(std::floor(py));
        const float z = sz.at(x, y);
        const float* nv = sn.pixel(x, y);
        float best = INFINITY;
        int bestIndex = y * w + x;
        for (int dy = 0; dy < 2; ++dy)
          for (int dx = 0; dx < 2; ++dx) {
            const int qx = x0 + dx, qy = y0 + dy;
            if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;  // Fig. 7: no guide outside the image
            const float zg = gz.at(qx, qy);
            const float* ng = gn.pixel(qx, qy);
            const float scale = std::max({z, zg, 1e-12f});
            const float cosine = nv[0] * ng[0] + nv[1] * ng[1] + nv[2] * ng[2];
            const float d = std::abs(z - zg) / scale + settings.normalWeight * (1.0f - cosine);
            // Ties go to the sample's own pixel, then in scan order.
            const bool own = qx == x && qy == y;
            if (d < best || (d == best && own)) {
              best = d;
              bestIndex = qy * w + qx;
            }
          }
        a[size_t(y) * w + x] = bestIndex;
      }
    });
    for (int i : a) ++count_[size_t(i)];  // sequential: guides receive from several pixels
  }

  // Eq. 7 on every radiance buffer (the guides and all samples carry the same ones).
  Frame out = guides;
  for (int bi = 0; bi < kBufferCount; ++bi) {
    const Buffer b = Buffer(bi);
    if (!isRadianceBuffer(b) || !guides.has(b)) continue;
    Image sum = guides[b];
    for (size_t k = 0; k < n; ++k) {
      const Image& src = s.samples[k][b];
      const std::vector<int>& a = assign_[k];
      for (int i = 0; i < w * h; ++i) {
        const float* v = src.pixel(i % w, i / w);
        float* o = sum.pixel(a[size_t(i)] % w, a[size_t(i)] / w);
        for (int c = 0; c < 3; ++c) o[c] += v[c];
      }
    }
    parallelRows(h, [&](int y) {
      for (int x = 0; x < w; ++x) {
        const float inv = 1.0f / float(count_[size_t(y) * w + x]);
        float* o = sum.pixel(x, y);
        for (int c = 0; c < 3; ++c) o[c] *= inv;
      }
    });
    out[b] = std::move(sum);
  }
  return out;
}

Image GuideRays::denoise(Denoiser& denoiser, const Frame& guides, const GuideRaySamples& samples,
                         const GuideRaySettings& settings) {
  passes_.clear();
#if defined(RTD_HAS_VULKAN)
  if (denoiser.backend() == Backend::Vulkan) {
    validate(guides, samples);
    width_ = height_ = 0;  // the assignment stays on the device
    assign_.clear();
    count_.clear();
    if (!gpu_) gpu_ = std::make_unique<detail::GuideRaysGpu>();
    return gpu_->denoise(denoiser, guides, samples, settings);
  }
#endif
  using Clock = std::chrono::steady_clock;
  auto ms = [](Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); };
  const auto t0 = Clock::now();
  const Frame mixed = premix(guides, samples, settings);
  const auto t1 = Clock::now();
  Image filtered(guides.width, guides.height, 3);
  denoiser.denoise(mixed.inputs(), filtered.view());
  const auto t2 = Clock::now();
  Image out = resolve(filtered);
  passes_ = {{"guideRays.premix", ms(t1 - t0)}, {"guideRays.resolve", ms(Clock::now() - t2)}};
  return out;
}

Image GuideRays::resolve(const Image& filtered) const {
  const int w = width_, h = height_;
  if (w == 0) throw Error("guide rays: resolve() before premix()");
  checkSize(filtered, w, h, 3, "the filtered image");
  const float inv = 1.0f / float(assign_.size() + 1);
  Image out(w, h, 3);
  parallelRows(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      float sum[3] = {filtered.at(x, y, 0), filtered.at(x, y, 1), filtered.at(x, y, 2)};  // the guide itself
      for (const std::vector<int>& a : assign_) {
        const float* v = filtered.pixel(a[i] % w, a[i] / w);
        for (int c = 0; c < 3; ++c) sum[c] += v[c];
      }
      for (int c = 0; c < 3; ++c) out.at(x, y, c) = sum[c] * inv;
    }
  });
  return out;
}

}  // namespace rtd
