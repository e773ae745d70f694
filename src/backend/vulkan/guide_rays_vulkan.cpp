// Supersampling with guide rays on the Vulkan backend (see guide_rays_vulkan.h).
#if defined(RTD_HAS_VULKAN)
#include "backend/vulkan/guide_rays_vulkan.h"

#include <cstring>
#include <vector>

#include "backend/vulkan/vulkan_denoiser.h"
#include "core/frame_data.h"
#include "rtd/error.h"

namespace rtd::detail {

namespace {

void ensure(vk::Context& ctx, vk::DeviceBuffer& b, size_t bytes, bool hostVisible) {
  if (b.empty() || b.size() < bytes) b = vk::DeviceBuffer(ctx, bytes, hostVisible);
}

constexpr Format kFloatFormats[] = {Format::Undefined, Format::Float, Format::Float2, Format::Float3, Format::Float4};

}  // namespace

Image GuideRaysGpu::denoise(Denoiser& denoiser, const Frame& g, const GuideRaySamples& s,
                            const GuideRaySettings& settings) {
  auto* d = dynamic_cast<vk::VulkanDenoiserBase*>(&denoiser);
  if (!d) throw Error("guide rays: the denoiser was not created on a Vulkan device");
  vk::Context& ctx = d->context();
  if (ctx_ != &ctx) {  // a denoiser of another device: its own buffers
    *this = GuideRaysGpu();
    ctx_ = &ctx;
  }
  const int w = g.width, h = g.height;
  const size_t n = size_t(w) * h, k = s.samples.size();

  // Everything the passes read, staged back to back in one host-visible buffer; each device
  // buffer is then one copy (a buffer's samples are contiguous there and in the staging).
  struct Upload {
    const float* data;
    size_t bytes;
    vk::DeviceBuffer* dst;
  };
  std::vector<Upload> uploads;
  auto stage = [&](vk::DeviceBuffer& dst, size_t bytes, const std::vector<const Image*>& images) {
    ensure(ctx, dst, bytes, false);
    for (const Image* img : images) uploads.push_back({img->pixels.data(), img->pixels.size() * 4, &dst});
  };
  auto ofSamples = [&](Buffer b) {
    std::vector<const Image*> v;
    for (const Frame& f : s.samples) v.push_back(&f[b]);
    return v;
  };
  std::vector<Buffer> radiance;
  for (int i = 0; i < kBufferCount; ++i) {
    const Buffer b = Buffer(i);
    if (!g.has(b)) continue;
    stage(guide_[i], g[b].pixels.size() * 4, {&g[b]});
    if (!isRadianceBuffer(b)) continue;
    radiance.push_back(b);
    stage(samples_[i], k * n * 12, ofSamples(b));
    ensure(ctx, mixed_[i], n * 12, false);
  }
  stage(sampleDepth_, k * n * 4, ofSamples(Buffer::Depth));
  stage(sampleNormal_, k * n * 12, ofSamples(Buffer::Normal));
  std::vector<const Image*> offsets;
  for (const Image& o : s.offsets) offsets.push_back(&o);
  stage(offsets_, k * n * 8, offsets);
  ensure(ctx, assigned_, k * n * 4, false);
  ensure(ctx, filtered_, n * 12, false);
  ensure(ctx, resolved_, n * 12, false);
  ensure(ctx, readback_, n * 12, true);
  size_t total = 0;
  for (const Upload& u : uploads) total += u.bytes;
  ensure(ctx, staging_, total, true);
  struct Copy {
    vk::DeviceBuffer* dst;
    size_t srcOffset, bytes;
  };
  std::vector<Copy> copies;
  size_t at = 0;
  for (const Upload& u : uploads) {
    std::memcpy(static_cast<char*>(staging_.mapped()) + at, u.data, u.bytes);
    if (!copies.empty() && copies.back().dst == u.dst) copies.back().bytes += u.bytes;
    else copies.push_back({u.dst, at, u.bytes});
    at += u.bytes;
  }

  VulkanFrameInputs in;
  in.width = w;
  in.height = h;
  in.camera = g.camera;
  in.cameraCut = g.cut;
  for (int i = 0; i < kBufferCount; ++i)
    if (g.has(Buffer(i)))
      in.buffers[i] = isRadianceBuffer(Buffer(i)) ? VulkanBufferView{mixed_[i].handle(), 0, Format::Float3}
                                                  : VulkanBufferView{guide_[i].handle(), 0, kFloatFormats[g.buffers[i].channels]};

  struct AssignPC {
    uint32_t width, height, samples;
    float normalWeight;
  } assignPc{uint32_t(w), uint32_t(h), uint32_t(k), settings.normalWeight};
  struct PC {
    uint32_t width, height, samples;
  } pc{uint32_t(w), uint32_t(h), uint32_t(k)};
  const std::function<void(vk::Recorder&)> before = [&](vk::Recorder& rec) {
    // Buffers this object may reallocate: no descriptor set of them is kept.
    for (const vk::DeviceBuffer* b : {&sampleDepth_, &sampleNormal_, &offsets_, &assigned_, &filtered_, &resolved_})
      rec.external(b->handle());
    for (int i = 0; i < kBufferCount; ++i)
      for (const vk::DeviceBuffer* b : {&guide_[i], &samples_[i], &mixed_[i]})
        if (!b->empty()) rec.external(b->handle());
    rec.pass("guideRays.upload");
    for (const Copy& c : copies) rec.copy(staging_, *c.dst, c.bytes, c.srcOffset, 0);
    rec.pass("guideRays.premix");
    if (k)
      rec.dispatch("guide_assign",
                   {guide_[int(Buffer::Depth)], guide_[int(Buffer::Normal)], sampleDepth_, sampleNormal_, offsets_, assigned_},
                   assignPc, w, h);
    for (Buffer b : radiance)
      rec.dispatch("guide_premix", {guide_[int(b)], samples_[int(b)], assigned_, mixed_[int(b)]}, pc, w, h);
  };
  const std::function<void(vk::Recorder&)> after = [&](vk::Recorder& rec) {
    rec.pass("guideRays.resolve");
    rec.dispatch("guide_resolve", {filtered_, assigned_, resolved_}, pc, w, h);
    rec.copy(resolved_, readback_, n * 12);
  };
  d->denoiseGpuAround(in, VulkanBufferView{filtered_.handle(), 0, Format::Float3}, before, after);

  Image out(w, h, 3);
  std::memcpy(out.pixels.data(), readback_.mapped(), n * 12);
  return out;
}

}  // namespace rtd::detail
#endif
