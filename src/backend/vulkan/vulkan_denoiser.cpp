#include "backend/vulkan/vulkan_denoiser.h"

#include <algorithm>
#include <chrono>
#include <cstring>

#include "core/api_guard.h"
#include "core/frame_data.h"
#include "core/half.h"
#include "core/sanitize.h"
#include "core/timer.h"
#include "core/validate.h"

namespace rtd::vk {

namespace {

constexpr uint32_t kMaxQueries = 64;

std::string describe(Buffer b) { return "buffer '" + std::string(bufferName(b)) + "'"; }

// Input image formats (rtd/vulkan.h): channels and the import shader for their texel type.
// Sampling these formats is a mandatory Vulkan feature, so no format query is needed.
struct InputImageFormat {
  VkFormat format;
  int channels;
  const char* shader;
};
constexpr InputImageFormat kInputImageFormats[] = {
    {VK_FORMAT_R32G32B32A32_SFLOAT, 4, "import_image_float"},
    {VK_FORMAT_R16G16B16A16_SFLOAT, 4, "import_image_float"},
    {VK_FORMAT_R32G32_SFLOAT, 2, "import_image_float"},
    {VK_FORMAT_R16G16_SFLOAT, 2, "import_image_float"},
    {VK_FORMAT_R32_SFLOAT, 1, "import_image_float"},
    {VK_FORMAT_R16_SFLOAT, 1, "import_image_float"},
    {VK_FORMAT_R8G8B8A8_UNORM, 4, "import_image_float"},
    {VK_FORMAT_R16G16B16A16_UNORM, 4, "import_image_float"},
    {VK_FORMAT_A2B10G10R10_UNORM_PACK32, 4, "import_image_float"},
    {VK_FORMAT_B10G11R11_UFLOAT_PACK32, 3, "import_image_float"},
    {VK_FORMAT_R32_SINT, 1, "import_image_int"},
    {VK_FORMAT_R32_UINT, 1, "import_image_uint"},
};

// import.comp's source type of a buffer view's format.
uint32_t importType(Format f) { return f == Format::Int32 ? 1 : isHalf(f) ? 2 : 0; }

const InputImageFormat* inputImageFormat(VkFormat f) {
  for (const auto& e : kInputImageFormats)
    if (e.format == f) return &e;
  return nullptr;
}

}  // namespace

VulkanDenoiserBase::VulkanDenoiserBase(Context& ctx) : keepAlive_(ctx.weak_from_this().lock()), ctx_(ctx), descriptors_(ctx) {
  VkCommandPoolCreateInfo pi{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pi.queueFamilyIndex = ctx.queueFamily();
  check(vkCreateCommandPool(ctx.device(), &pi, nullptr, &pool_), "vkCreateCommandPool");
  VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = pool_;
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = 1;
  check(vkAllocateCommandBuffers(ctx.device(), &ai, &cmd_), "vkAllocateCommandBuffers");
  VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  check(vkCreateFence(ctx.device(), &fi, nullptr, &fence_), "vkCreateFence");
  if (ctx.timestamps()) {
    VkQueryPoolCreateInfo qi{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    qi.queryType = VK_QUERY_TYPE_TIMESTAMP;
    qi.queryCount = kMaxQueries;
    check(vkCreateQueryPool(ctx.device(), &qi, nullptr, &queries_), "vkCreateQueryPool");
  }
  const MemoryOwnerScope owner(memoryOwner_);
  // Sanitize counters, three per buffer (shaders/sanitize.glsl).
  counter_ = DeviceBuffer(ctx, kBufferCount * 3 * sizeof(uint32_t), true);
  for (auto& f : frames_) f.camera = DeviceBuffer(ctx, 32 * sizeof(float), false);
}

VulkanDenoiserBase::~VulkanDenoiserBase() {
  vkDeviceWaitIdle(ctx_.device());
  if (queries_) vkDestroyQueryPool(ctx_.device(), queries_, nullptr);
  vkDestroyFence(ctx_.device(), fence_, nullptr);
  vkDestroyCommandPool(ctx_.device(), pool_, nullptr);
}

std::vector<Buffer> VulkanDenoiserBase::usedBuffers(bool frameHasMotion) const {
  return importedBuffers(requiredBuffers(), extraBuffers(), reprojectionSettings(), frameHasMotion);
}

void VulkanDenoiserBase::prepare(int w, int h, bool cameraCut) {
  if (w != width_ || h != height_) {
    // Old buffers may still be in flight (commands recorded into the application's buffer).
    vkDeviceWaitIdle(ctx_.device());
    descriptors_.clear();
    for (auto& f : frames_) {
      for (auto& p : f.planes) p = Planes{};
      f.present.fill(false);
    }
    width_ = w;
    height_ = h;
    resizeHistory(w, h);
    reset();
  } else if (cameraCut) {
    reset();
  }
}

void VulkanDenoiserBase::record(VkCommandBuffer cmd, const std::vector<Import>& imports, const Camera& camera,
                                const ConventionTransform& conventions, const Export& out) {
  Recorder rec = beginRecord(cmd, imports, camera, conventions, out);
  resultHasEmission_ = false;
  const Planes& result = process(rec, frames_[cur_], hasPrevious_ ? &frames_[cur_ ^ 1] : nullptr);
  endRecord(rec, result, out);
}

Recorder VulkanDenoiserBase::beginRecord(VkCommandBuffer cmd, const std::vector<Import>& imports, const Camera& camera,
                                         const ConventionTransform& conventions, const Export& out) {
  GpuFrame& f = frames_[cur_];
  f.width = width_;
  f.height = height_;
  f.present.fill(false);
  f.cameraValue = camera;
  for (const auto& im : imports) {
    Planes& p = f.planes[int(im.which)];
    if (p.width != width_ || p.height != height_) p.allocate(ctx_, width_, height_, bufferChannelCount(im.which));
    f.present[int(im.which)] = true;
  }

  // Whatever the application wrote before (its input buffers) is visible to our reads.
  VkMemoryBarrier in{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  in.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
  in.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &in, 0, nullptr, 0,
                       nullptr);
  if (queries_) vkCmdResetQueryPool(cmd, queries_, 0, kMaxQueries);

  Recorder rec(ctx_, descriptors_, cmd, queries_, kMaxQueries);
  for (const auto& im : imports) {
    if (im.source.view) rec.external(im.source.view);
    else rec.external(im.source.buffer);
  }
  if (out.target.view) rec.external(out.target.view);
  else rec.external(out.target.buffer);
  rec.fill(counter_, 0);
  float matrices[32];
  std::memcpy(matrices, camera.worldToCamera.data(), 16 * sizeof(float));
  std::memcpy(matrices + 16, camera.projection.data(), 16 * sizeof(float));
  vkCmdUpdateBuffer(cmd, f.camera.handle(), 0, sizeof matrices, matrices);
  if (conventions.jitter && hasPrevious_) {
    // The previous camera as this jittered frame's reprojection sees it (core/conventions.h).
    GpuFrame& p = frames_[cur_ ^ 1];
    p.cameraValue = jitterCompensated(p.cameraValue, conventions, width_, height_);
    std::memcpy(matrices, p.cameraValue.worldToCamera.data(), 16 * sizeof(float));
    std::memcpy(matrices + 16, p.cameraValue.projection.data(), 16 * sizeof(float));
    vkCmdUpdateBuffer(cmd, p.camera.handle(), 0, sizeof matrices, matrices);
  }
  rec.barrier();
  if (before_) (*before_)(rec);

  rec.pass("import");
  for (const auto& im : imports) {
    const ValueRange range = importRange(im.which);
    const uint32_t counter = 3 * uint32_t(im.which);
    if (im.imageShader) {
      struct PC {
        uint32_t width, height, channels, counter;
        float lo, hi;
      } pc{uint32_t(width_), uint32_t(height_), uint32_t(bufferChannelCount(im.which)), counter, range.lo, range.hi};
      rec.dispatch(im.imageShader, {im.source, f.planes[int(im.which)], counter_}, pc, width_, height_);
      continue;
    }
    struct PC {
      uint32_t width, height, srcOffset, pixelStride, rowStride, channels, type, counter;
      float lo, hi;
    } pc{uint32_t(width_), uint32_t(height_), im.offsetWords, im.pixelStrideWords, im.rowStrideWords,
         uint32_t(bufferChannelCount(im.which)), im.type, counter, range.lo, range.hi};
    rec.dispatch("import", {im.source, f.planes[int(im.which)], counter_}, pc, width_, height_);
  }
  // Unit vectors renormalized (renormalizeRow in the CPU import).
  for (const auto& im : imports) {
    if (!isUnitVectorBuffer(im.which)) continue;
    struct PC {
      uint32_t width, height, counter;
    } pc{uint32_t(width_), uint32_t(height_), 3 * uint32_t(im.which)};
    rec.dispatch("sanitize_unit_vectors", {f.planes[int(im.which)], counter_}, pc, width_, height_);
  }

  const bool emission = f.present[int(Buffer::Emission)];
  if (emission) {
    // The renderer counts primary-hit emission in color, direct and diffuse (frame_data.cpp).
    struct PC {
      uint32_t width, height;
    } pc{uint32_t(width_), uint32_t(height_)};
    for (Buffer b : {Buffer::Color, Buffer::Direct, Buffer::Diffuse})
      if (f.present[int(b)])
        rec.dispatch("separate_emission", {f.planes[int(b)], f.planes[int(Buffer::Emission)]}, pc, width_, height_);
  }

  if (conventions.convertsPlanes()) {
    rec.pass("conventions");
    struct PC {
      uint32_t width, height, mode;
      float a[9];
    };
    const ConventionTransform& t = conventions;
    if (t.motion && f.has(Buffer::Motion)) {
      PC pc{uint32_t(width_), uint32_t(height_), 0, {t.motionScale[0], t.motionScale[1], t.motionOffset[0], t.motionOffset[1]}};
      rec.dispatch("conventions", {f.planes[int(Buffer::Motion)]}, pc, width_, height_);
    }
    if (t.normals && f.has(Buffer::Normal)) {
      PC pc{uint32_t(width_), uint32_t(height_), 1, {}};
      std::memcpy(pc.a, t.normalMatrix, sizeof pc.a);
      rec.dispatch("conventions", {f.planes[int(Buffer::Normal)]}, pc, width_, height_);
    }
    if (t.depth && f.has(Buffer::Depth)) {
      PC pc{uint32_t(width_), uint32_t(height_), 2, {t.ndcScale, t.ndcOffset, t.p22, t.p23, t.p32, t.p33}};
      rec.dispatch("conventions", {f.planes[int(Buffer::Depth)]}, pc, width_, height_);
    }
  }

  if (f.present[int(Buffer::HiddenArea)]) {
    // The hidden area carries nothing (applyHiddenArea on the CPU): radiance and normals 0.
    struct PC {
      uint32_t width, height, channels;
    } pc{uint32_t(width_), uint32_t(height_), 0};
    for (int b = 0; b < kBufferCount; ++b)
      if (f.present[b] && (isRadianceBuffer(Buffer(b)) || Buffer(b) == Buffer::Normal)) {
        pc.channels = uint32_t(bufferChannelCount(Buffer(b)));
        rec.dispatch("hidden_area", {f.planes[b], f.planes[int(Buffer::HiddenArea)]}, pc, width_, height_);
      }
  }
  return rec;
}

void VulkanDenoiserBase::endRecord(Recorder& rec, const Planes& result, const Export& out) {
  GpuFrame& f = frames_[cur_];
  const VkCommandBuffer cmd = rec.commandBuffer();
  const bool addEmission = f.present[int(Buffer::Emission)] && !resultHasEmission_;

  rec.pass("export");
  if (out.imageShader) {
    struct PC {
      uint32_t width, height, addEmission;
    } pc{uint32_t(width_), uint32_t(height_), addEmission};
    rec.dispatch(out.imageShader, {result, out.target, addEmission ? f.planes[int(Buffer::Emission)] : result}, pc,
                 width_, height_);
  } else {
    struct PC {
      uint32_t width, height, dstOffset, pixelStride, rowStride, channels, addEmission;
    } pc{uint32_t(width_), uint32_t(height_), out.offsetWords, out.pixelStrideWords, out.rowStrideWords, out.channels,
         addEmission};
    rec.dispatch("export", {result, out.target, addEmission ? f.planes[int(Buffer::Emission)] : result}, pc, width_,
                 height_);
  }
  if (after_) (*after_)(rec);
  rec.endPasses();

  // Our writes are visible to whatever comes next: the host read-back or the application.
  VkMemoryBarrier done{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  done.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  done.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT | VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_ALL_COMMANDS_BIT | VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &done, 0, nullptr, 0,
                       nullptr);
  recordedPasses_ = rec.passNames();
  recordedQueries_ = rec.queriesWritten();
  cur_ ^= 1;
  hasPrevious_ = true;
}

void VulkanDenoiserBase::submitAndWait() {
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmd_;
  check(vkQueueSubmit(ctx_.queue(), 1, &si, fence_), "vkQueueSubmit");
  VkResult r = vkWaitForFences(ctx_.device(), 1, &fence_, VK_TRUE, UINT64_MAX);
  vkResetFences(ctx_.device(), 1, &fence_);
  check(r, "vkWaitForFences");
}

void VulkanDenoiserBase::readSanitizeCounts(FrameStats& stats) const {
  const uint32_t* c = static_cast<const uint32_t*>(counter_.mapped());
  stats.sanitizedValues = 0;
  for (int b = 0; b < kBufferCount; ++b) {
    SanitizeCounts& s = stats.sanitized[size_t(b)];
    s = {c[3 * b], c[3 * b + 1], c[3 * b + 2]};
    stats.sanitizedValues += s.total();
  }
}

bool VulkanDenoiserBase::readTimings(FrameStats& stats, bool wait) {
  if (!queries_ || recordedQueries_ < 2) return false;
  uint64_t t[kMaxQueries];
  VkResult r = vkGetQueryPoolResults(ctx_.device(), queries_, 0, recordedQueries_, sizeof t, t, sizeof(uint64_t),
                                     VK_QUERY_RESULT_64_BIT | (wait ? VK_QUERY_RESULT_WAIT_BIT : 0));
  if (r != VK_SUCCESS) return false;
  const double toMs = ctx_.timestampPeriod() * 1e-6;
  for (uint32_t k = 0; k + 1 < recordedQueries_ && k < recordedPasses_.size(); ++k)
    stats.passes.push_back({recordedPasses_[k], double(t[k + 1] - t[k]) * toMs});
  stats.passes.push_back({"gpu total", double(t[recordedQueries_ - 1] - t[0]) * toMs});
  // What an engine with its buffers already on the GPU pays: everything between the import of
  // the frame and the export of the result (on a discrete GPU the host path's import reads
  // host memory over PCIe, which says nothing about the filter).
  const size_t last = recordedPasses_.size() - 1;
  if (recordedPasses_.size() >= 3 && recordedPasses_.front() == "import" && recordedPasses_[last] == "export" &&
      last + 1 < recordedQueries_)
    stats.passes.push_back({"gpu filter", double(t[last] - t[1]) * toMs});
  return true;
}

std::vector<MemoryUse> VulkanDenoiserBase::memoryUse() const {
  uint64_t frames = 0;
  for (const GpuFrame& f : frames_) {
    for (const Planes& p : f.planes) frames += p.buffer.allocatedBytes();
    frames += f.camera.allocatedBytes();
  }
  std::vector<MemoryUse> out{{"frames", frames}};
  const uint64_t deviceLocal = memoryOwner_->deviceLocal;
  uint64_t rest = deviceLocal - std::min(deviceLocal, frames);
  for (const MemoryUse& m : methodMemory()) {
    out.push_back(m);
    rest -= std::min(rest, m.bytes);
  }
  out.push_back({"planes", rest});
  out.push_back({"staging", memoryOwner_->hostVisible});
  return out;
}

void VulkanDenoiserBase::denoise(const FrameInputs& in, const ImageView& output) {
  const MemoryOwnerScope owner(memoryOwner_);
  guarded("denoise", [&] { denoiseHost(in, output); });
}

void VulkanDenoiserBase::denoiseHost(const FrameInputs& in, const ImageView& output) {
  HostFrame frame = stageHost(in, output);
  check(vkResetCommandBuffer(cmd_, 0), "vkResetCommandBuffer");
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(cmd_, &bi), "vkBeginCommandBuffer");
  record(cmd_, frame.imports, frame.camera, frame.conventions, frame.out);
  check(vkEndCommandBuffer(cmd_), "vkEndCommandBuffer");
  submitAndWait();
  finishHost(frame, output);
}

void VulkanDenoiserBase::denoiseTwoViews(VulkanDenoiserBase& a, VulkanDenoiserBase& b, const FrameInputs& inA,
                                         const FrameInputs& inB, const ImageView& outA, const ImageView& outB,
                                         const std::function<void(Recorder&)>& exchange) {
  // Each view's calls in its own MemoryOwnerScope; the exchange through a's.
  auto as = [](VulkanDenoiserBase& v, auto&& call) -> decltype(auto) {
    const MemoryOwnerScope owner(v.memoryOwner_);
    return call();
  };
  guarded("denoise", [&] {
    HostFrame fa = as(a, [&] { return a.stageHost(inA, outA); });
    HostFrame fb = as(b, [&] { return b.stageHost(inB, outB); });
    const VkCommandBuffer cmd = a.cmd_;
    check(vkResetCommandBuffer(cmd, 0), "vkResetCommandBuffer");
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    check(vkBeginCommandBuffer(cmd, &bi), "vkBeginCommandBuffer");
    auto previous = [](VulkanDenoiserBase& v) { return v.hasPrevious_ ? &v.frames_[v.cur_ ^ 1] : nullptr; };
    auto front = [&](VulkanDenoiserBase& v, const HostFrame& f) {
      return as(v, [&] {
        Recorder r = v.beginRecord(cmd, f.imports, f.camera, f.conventions, f.out);
        v.resultHasEmission_ = false;
        v.processFront(r, v.frames_[v.cur_], previous(v));
        r.pass("(other eye)");
        return r;
      });
    };
    auto back = [&](VulkanDenoiserBase& v, Recorder& r, const HostFrame& f) {
      as(v, [&] { v.endRecord(r, v.processBack(r, v.frames_[v.cur_], previous(v)), f.out); });
    };
    Recorder ra = front(a, fa);
    Recorder rb = front(b, fb);
    ra.barrier();  // b's writes (recorded through the other recorder) before a reads them
    ra.pass("eyeReprojection");
    as(a, [&] { exchange(ra); });
    back(a, ra, fa);
    rb.barrier();
    back(b, rb, fb);
    check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
    a.submitAndWait();
    a.finishHost(fa, outA);
    b.finishHost(fb, outB);
  });
}

VulkanDenoiserBase::HostFrame VulkanDenoiserBase::stageHost(const FrameInputs& in, const ImageView& output) {
  HostFrame frame;
  frame.start = std::chrono::steady_clock::now();
  FrameStats& stats = frame.stats;
  // Everything is checked before history is touched, as on the CPU (core/validate.h).
  checkInputViews(in, requiredBuffers());
  const int w = in[Buffer::Color].width, h = in[Buffer::Color].height;
  checkOutputView(output, w, h);
  frame.conventions = conventionTransform(in.conventions, in.camera, w, h, in.has(Buffer::Normal));

  // Validate every used buffer before touching history, then pack them into the staging buffer
  // row by row, keeping each view's pixel layout (the import shader applies the strides).
  // Each buffer gets its own aligned range of the staging buffer, so no binding is larger than
  // one image (maxStorageBufferRange is 128 MiB on some devices).
  const size_t align = std::max<size_t>(ctx_.limits().minStorageBufferOffsetAlignment, 16);
  auto alignUp = [](size_t n, size_t a) { return (n + a - 1) / a * a; };
  std::vector<Buffer> used;
  size_t bytes = 0;
  for (Buffer b : usedBuffers(in.has(Buffer::Motion))) {
    const ImageView& v = in[b];
    if (v.empty()) continue;
    used.push_back(b);
    bytes += alignUp(v.bytesPerPixel() * size_t(w) * h, align);
  }
  std::vector<Import> imports;
  {
    PassTimer t(stats, "upload (host)");
    if (upload_.size() < bytes) {
      vkDeviceWaitIdle(ctx_.device());
      descriptors_.clear();
      upload_ = DeviceBuffer(ctx_, bytes, true);
    }
    size_t offset = 0;
    for (Buffer b : used) {
      const ImageView& v = in[b];
      const size_t rowBytes = v.bytesPerPixel() * size_t(w);
      char* dst = static_cast<char*>(upload_.mapped()) + offset;
      for (int y = 0; y < h; ++y) std::memcpy(dst + size_t(y) * rowBytes, v.pixel<char>(0, y), rowBytes);
      // Strides in the shader's units (words; 16-bit units for halves); a range a whole number of words.
      const size_t unit = size_t(channelBytes(v.format));
      imports.push_back({b, Binding(upload_.handle(), offset, alignUp(rowBytes * h, 4)), 0,
                         uint32_t(v.bytesPerPixel() / unit), uint32_t(rowBytes / unit), importType(v.format)});
      offset += alignUp(rowBytes * h, align);
    }
  }
  prepare(w, h, in.cameraCut);
  const uint32_t outChannels = uint32_t(output.channels());
  const size_t outBytes = size_t(w) * h * outChannels * 4;
  if (readback_.size() < outBytes) {
    vkDeviceWaitIdle(ctx_.device());
    descriptors_.clear();
    readback_ = DeviceBuffer(ctx_, outBytes, true);
  }

  frame.imports = std::move(imports);
  frame.out = {Binding(readback_), 0, outChannels, outChannels * uint32_t(w), outChannels};
  frame.camera = in.camera;
  frame.width = w;
  frame.height = h;
  frame.outChannels = outChannels;
  return frame;
}

void VulkanDenoiserBase::finishHost(HostFrame& frame, const ImageView& output) {
  FrameStats& stats = frame.stats;
  const int w = frame.width, h = frame.height;
  const uint32_t outChannels = frame.outChannels;
  readTimings(stats, true);
  {
    PassTimer t(stats, "download (host)");
    const float* src = static_cast<const float*>(readback_.mapped());
    for (int y = 0; y < h; ++y) {
      const float* row = src + size_t(y) * w * outChannels;
      if (isHalf(output.format)) {
        const bool packed = output.bytesPerPixel() == outChannels * 2;
        if (packed) floatsToHalves(row, output.pixel<char>(0, y), size_t(w) * outChannels);
        else
          for (int x = 0; x < w; ++x) floatsToHalves(row + size_t(x) * outChannels, output.pixel<char>(x, y), outChannels);
      } else if (output.bytesPerPixel() == outChannels * 4) {
        std::memcpy(output.pixel<float>(0, y), row, size_t(w) * outChannels * 4);
      } else {
        for (int x = 0; x < w; ++x) std::memcpy(output.pixel<float>(x, y), row + size_t(x) * outChannels, outChannels * 4);
      }
    }
  }
  readSanitizeCounts(stats);
  stats.pixels = uint64_t(w) * h;
  stats.totalMilliseconds =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - frame.start).count();
  stats.notes = notes_;
  stats.memory = memoryUse();
  stats_ = std::move(stats);
}

void VulkanDenoiserBase::denoiseGpu(const VulkanFrameInputs& in, const VulkanBufferView& output, VkCommandBuffer cmd) {
  const MemoryOwnerScope owner(memoryOwner_);
  guarded("denoiseVulkan", [&] { denoiseIntoBuffer(in, output, cmd); });
}

void VulkanDenoiserBase::denoiseGpu(const VulkanFrameInputs& in, const VulkanImageView& output, VkCommandBuffer cmd) {
  const MemoryOwnerScope owner(memoryOwner_);
  guarded("denoiseVulkan", [&] { denoiseIntoImage(in, output, cmd); });
}

void VulkanDenoiserBase::denoiseGpuAround(const VulkanFrameInputs& in, const VulkanBufferView& output,
                                          const std::function<void(Recorder&)>& before,
                                          const std::function<void(Recorder&)>& after) {
  struct Reset {
    VulkanDenoiserBase& d;
    ~Reset() { d.before_ = d.after_ = nullptr; }
  } reset{*this};
  before_ = &before;
  after_ = &after;
  denoiseGpu(in, output, VK_NULL_HANDLE);
}

void VulkanDenoiserBase::denoiseIntoBuffer(const VulkanFrameInputs& in, const VulkanBufferView& output,
                                           VkCommandBuffer cmd) {
  if (output.empty() || (output.format != Format::Float3 && output.format != Format::Float4))
    throw Error("output VkBuffer view must be set and Float3 or Float4");
  checkImageSize("VulkanFrameInputs", in.width, in.height);
  Export ex{};
  ex.channels = uint32_t(channelCount(output.format));
  bindBufferView(output, "output", ex.channels, in.width, in.height, ex.target, ex.offsetWords, ex.pixelStrideWords,
                 ex.rowStrideWords);
  denoiseGpu(in, ex, cmd);
}

void VulkanDenoiserBase::denoiseIntoImage(const VulkanFrameInputs& in, const VulkanImageView& output,
                                          VkCommandBuffer cmd) {
  Export ex{};
  if (output.empty()) throw Error("output VkImageView must be set");
  if (output.format == VK_FORMAT_R32G32B32A32_SFLOAT) ex.imageShader = "export_image_rgba32f";
  else if (output.format == VK_FORMAT_R16G16B16A16_SFLOAT) ex.imageShader = "export_image_rgba16f";
  else
    throw Error("output image: format " + std::to_string(int(output.format)) +
                " is not supported (R32G32B32A32_SFLOAT or R16G16B16A16_SFLOAT, as a storage image)");
  if (output.layout != VK_IMAGE_LAYOUT_GENERAL) throw Error("output image: layout must be VK_IMAGE_LAYOUT_GENERAL (a storage image)");
  ex.target = Binding::image(output.view, output.layout);
  ex.channels = 4;
  denoiseGpu(in, ex, cmd);
}

void VulkanDenoiserBase::bindBufferView(const VulkanBufferView& v, const std::string& what, uint32_t channels, int w,
                                        int h, Binding& binding, uint32_t& offsetUnits, uint32_t& pixelUnits,
                                        uint32_t& rowUnits) const {
  // A view as a binding: the offset rounded down to the alignment the device needs, the rest
  // passed to the shader in words; the range covers exactly the pixels read or written.
  // Units are 32-bit words, or 16-bit halves for Half* views.
  const uint32_t unit = uint32_t(channelBytes(v.format));
  const VkDeviceSize align = std::max<VkDeviceSize>(ctx_.limits().minStorageBufferOffsetAlignment, 4);
  if (channelCount(v.format) == 0) throw Error(what + " has no format (Format::Undefined or an unknown value)");
  if (v.offset % unit) throw Error(what + ": offset " + std::to_string(v.offset) + " must be a multiple of " + std::to_string(unit) + " bytes");
  checkStrides(what, v.format, v.pixelStride, v.rowStride, w);
  const uint32_t pixel = v.pixelStride ? v.pixelStride : uint32_t(channelCount(v.format)) * unit;
  const uint32_t row = v.rowStride ? v.rowStride : pixel * uint32_t(w);
  const VkDeviceSize base = v.offset / align * align;
  const VkDeviceSize end = VkDeviceSize(v.offset - base) + VkDeviceSize(h - 1) * row + VkDeviceSize(w - 1) * pixel +
                           channels * unit;
  binding = Binding(v.buffer, base, (end + 3) / 4 * 4);
  offsetUnits = uint32_t((v.offset - base) / unit);
  pixelUnits = pixel / unit;
  rowUnits = row / unit;
}

void VulkanDenoiserBase::denoiseGpu(const VulkanFrameInputs& in, const Export& ex, VkCommandBuffer cmd) {
  // Checked like host frames (core/validate.h) before history is touched: size, required
  // buffers, camera, and every buffer given, used by the method or not.
  const int w = in.width, h = in.height;
  checkImageSize("VulkanFrameInputs", w, h);
  if (!in.has(Buffer::Color)) throw Error("missing required " + describe(Buffer::Color));
  for (Buffer b : requiredBuffers())
    if (!in.has(b)) throw Error("missing required " + describe(b));
  checkCamera(in.camera);

  const ConventionTransform conventions = conventionTransform(in.conventions, in.camera, w, h, in.has(Buffer::Normal));
  const std::vector<Buffer> used = usedBuffers(in.has(Buffer::Motion));
  std::vector<Import> imports;
  for (int i = 0; i < kBufferCount; ++i) {
    const Buffer b = Buffer(i);
    if (!in.has(b)) continue;
    const VulkanImageView& image = in.image(b);
    if (!image.empty()) {
      const InputImageFormat* f = inputImageFormat(image.format);
      if (!f)
        throw Error(describe(b) + ": image format " + std::to_string(int(image.format)) +
                    " is not supported (rtd/vulkan.h lists the sampleable formats rtdenoise reads)");
      if (f->channels < bufferChannelCount(b))
        throw Error(describe(b) + " needs " + std::to_string(bufferChannelCount(b)) + " channels, the image format has " +
                    std::to_string(f->channels));
      if (image.layout != VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL && image.layout != VK_IMAGE_LAYOUT_GENERAL &&
          image.layout != VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL)
        throw Error(describe(b) + ": image layout " + std::to_string(int(image.layout)) +
                    " cannot be sampled (use VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL or GENERAL)");
      Import im{b, Binding::image(image.view, image.layout), 0, 0, 0, 0, f->shader};
      if (std::find(used.begin(), used.end(), b) != used.end()) imports.push_back(im);
      continue;
    }
    const VulkanBufferView& v = in[b];
    if (channelCount(v.format) < bufferChannelCount(b))
      throw Error(describe(b) + " needs " + std::to_string(bufferChannelCount(b)) + " channels, the view has " +
                  std::to_string(channelCount(v.format)));
    Import im{b, {}, 0, 0, 0, importType(v.format)};
    bindBufferView(v, describe(b), uint32_t(bufferChannelCount(b)), w, h, im.source, im.offsetWords,
                   im.pixelStrideWords, im.rowStrideWords);
    if (std::find(used.begin(), used.end(), b) != used.end()) imports.push_back(im);
  }

  const auto start = std::chrono::steady_clock::now();
  if (cmd) {
    // The previous frame recorded into the application's command buffer may have run by now.
    FrameStats previous;
    if (readTimings(previous, false)) {
      previous.pixels = uint64_t(width_) * height_;
      readSanitizeCounts(previous);
      previous.notes = notes_;
      previous.memory = memoryUse();
      stats_ = std::move(previous);
    }
    prepare(w, h, in.cameraCut);
    record(cmd, imports, in.camera, conventions, ex);
    return;
  }
  FrameStats stats;
  prepare(w, h, in.cameraCut);
  check(vkResetCommandBuffer(cmd_, 0), "vkResetCommandBuffer");
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(cmd_, &bi), "vkBeginCommandBuffer");
  record(cmd_, imports, in.camera, conventions, ex);
  check(vkEndCommandBuffer(cmd_), "vkEndCommandBuffer");
  submitAndWait();
  readTimings(stats, true);
  readSanitizeCounts(stats);
  stats.pixels = uint64_t(w) * h;
  stats.totalMilliseconds = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  stats.notes = notes_;
  stats.memory = memoryUse();
  stats_ = std::move(stats);
}

}  // namespace rtd::vk
