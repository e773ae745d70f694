// The Vulkan device layer: instance and device selection, buffers, compute pipelines built from
// the embedded SPIR-V, descriptor sets, command recording and timestamp queries. Every method's
// Vulkan implementation records its passes through a Recorder.
#pragma once
#include <vulkan/vulkan.h>

#include <algorithm>
#include <atomic>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "rtd/denoiser.h"
#include "rtd/vulkan.h"

namespace rtd::vk {

/// Throws rtd::Error("Vulkan: <what> failed (VK_ERROR_...)") unless r is VK_SUCCESS.
void check(VkResult r, const char* what);
const char* resultName(VkResult r);

/// One physical device as `rtdenoise devices` shows it.
struct PhysicalDeviceInfo {
  int index = 0;
  std::string name;
  std::string type;  ///< "discrete GPU", "integrated GPU", "virtual GPU", "CPU (software)", "other"
  std::string driver;
  uint32_t apiVersion = 0;
};

/// Every Vulkan 1.2+ device with a compute queue. Throws rtd::Error when there is no Vulkan
/// driver (no ICD) or no such device.
std::vector<PhysicalDeviceInfo> enumeratePhysicalDevices();

class Context;

/// Device memory held by one owner (a denoiser), by kind: each DeviceBuffer created while the
/// owner's MemoryOwnerScope is open on the thread adds its allocation here, and takes it away
/// when it is released, wherever it has been moved to by then (FrameStats::memory on Vulkan).
struct MemoryTally {
  std::atomic<uint64_t> deviceLocal{0}, hostVisible{0};
};

/// While it lives, the DeviceBuffers created on this thread count towards `owner` (null: no
/// owner's); scopes nest, the previous owner returns at the end.
class MemoryOwnerScope {
 public:
  explicit MemoryOwnerScope(std::shared_ptr<MemoryTally> owner);
  ~MemoryOwnerScope();
  MemoryOwnerScope(const MemoryOwnerScope&) = delete;
  MemoryOwnerScope& operator=(const MemoryOwnerScope&) = delete;

 private:
  std::shared_ptr<MemoryTally> previous_;
};

/// A VkBuffer with its memory; device-local, or host-visible and persistently mapped.
class DeviceBuffer {
 public:
  DeviceBuffer() = default;
  DeviceBuffer(Context& ctx, VkDeviceSize size, bool hostVisible);
  DeviceBuffer(DeviceBuffer&& o) noexcept { *this = std::move(o); }
  DeviceBuffer& operator=(DeviceBuffer&& o) noexcept;
  ~DeviceBuffer() { release(); }
  DeviceBuffer(const DeviceBuffer&) = delete;
  DeviceBuffer& operator=(const DeviceBuffer&) = delete;

  VkBuffer handle() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  /// The device memory behind it (VkMemoryRequirements::size: size() rounded up as the
  /// driver needs).
  VkDeviceSize allocatedBytes() const { return allocated_; }
  void* mapped() const { return mapped_; }
  bool empty() const { return buffer_ == VK_NULL_HANDLE; }
  void release();

 private:
  Context* ctx_ = nullptr;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceSize size_ = 0, allocated_ = 0;
  void* mapped_ = nullptr;
  bool hostVisible_ = false;
  std::shared_ptr<MemoryTally> owner_;  // the MemoryOwnerScope's at creation, or null
};

/// `count` planes of width*height 32-bit values (floats, or uints for bit fields) in one buffer,
/// plane c starting at element c*width*height: the GPU twin of the CPU's Plane/Plane3.
struct Planes {
  DeviceBuffer buffer;
  int width = 0, height = 0, count = 0;
  void allocate(Context& ctx, int w, int h, int n);
  VkBuffer handle() const { return buffer.handle(); }
  size_t planeSize() const { return size_t(width) * height; }
};
/// Allocates p where it is empty, for planes a pass allocates when it first runs (resize
/// releases them): the twin of allocateOnce in core/plane.h.
inline void allocateOnce(Planes& p, Context& ctx, int w, int h, int n) {
  if (p.buffer.empty()) p.allocate(ctx, w, h, n);
}

/// A compute pipeline for one embedded shader: descriptor set layout with one descriptor per
/// binding (0..bindings-1; storage buffers, or sampled / storage images where the shader
/// declares a texture or image) and a 128-byte push-constant block.
struct Pipeline {
  VkShaderModule module = VK_NULL_HANDLE;
  VkDescriptorSetLayout setLayout = VK_NULL_HANDLE;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkPipeline pipeline = VK_NULL_HANDLE;
  uint32_t bindings = 0;
  std::vector<VkDescriptorType> types;  ///< per binding, reflected from the SPIR-V
  uint32_t localSize[3] = {1, 1, 1};
};

/// A binding: a storage buffer and the byte range of it the shader sees, or an image view in
/// a layout (for the shaders' texture2D / image2D bindings: the application's VkImages).
struct Binding {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceSize offset = 0;
  VkDeviceSize range = VK_WHOLE_SIZE;
  VkImageView view = VK_NULL_HANDLE;
  VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
  Binding() = default;
  Binding(VkBuffer b, VkDeviceSize o = 0, VkDeviceSize r = VK_WHOLE_SIZE) : buffer(b), offset(o), range(r) {}
  Binding(const DeviceBuffer& b) : buffer(b.handle()) {}
  Binding(const Planes& p) : buffer(p.handle()) {}
  static Binding image(VkImageView v, VkImageLayout l) {
    Binding b;
    b.view = v;
    b.layout = l;
    return b;
  }
  auto key() const { return std::tie(buffer, offset, range, view, layout); }
  bool operator<(const Binding& o) const { return key() < o.key(); }
};


/// A Vulkan instance, device and compute queue (owned, or borrowed from the application), with
/// the pipelines of every embedded shader created on first use.
class Context : public std::enable_shared_from_this<Context> {
 public:
  /// Picks a device by DeviceDesc::vulkanDevice (index or case-insensitive name substring;
  /// empty: discrete > integrated > virtual > CPU). Throws rtd::Error when none fits.
  explicit Context(const DeviceDesc& desc);
  /// Borrows the application's device; destroys only what rtdenoise created on it.
  explicit Context(const VulkanDeviceDesc& handles);
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  VkDevice device() const { return device_; }
  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physicalDevice() const { return physical_; }
  VkQueue queue() const { return queue_; }
  uint32_t queueFamily() const { return family_; }
  const std::string& name() const { return name_; }
  bool timestamps() const { return timestampValidBits_ > 0; }
  /// Nanoseconds per timestamp tick.
  double timestampPeriod() const { return timestampPeriod_; }
  const VkPhysicalDeviceLimits& limits() const { return limits_; }
  /// Lowers limits().maxStorageBufferRange to `bytes` (never raises it), as on a device with
  /// that smaller limit: for the tests of the work split by it (BMFR's fit in several
  /// dispatches, otherwise reached only at ~4K).
  void capStorageBufferRange(uint32_t bytes) {
    limits_.maxStorageBufferRange = std::min(limits_.maxStorageBufferRange, bytes);
  }
  /// A small buffer bound where a shader's optional input is absent (its flag says so).
  const DeviceBuffer& dummy() const { return *dummy_; }
  /// Device memory of every DeviceBuffer alive on this context, of all owners (the reference
  /// the tests hold FrameStats::memory against).
  uint64_t liveBytes() const { return liveBytes_; }

  /// Memory type index for the requirements; host-visible (coherent) or device-local.
  uint32_t memoryType(uint32_t typeBits, bool hostVisible) const;
  /// The pipeline of embedded shader `name`; throws rtd::Error if there is no such shader.
  const Pipeline& pipeline(const std::string& name);

  /// Records with `record` into a one-time command buffer, submits it and waits (uploads,
  /// downloads, tests).
  template <class F> void runOnce(F&& record) {
    VkCommandBuffer cmd = beginOnce();
    record(cmd);
    endOnce(cmd);
  }
  /// Host data -> buffer (through a staging buffer) and back, synchronously.
  void upload(const DeviceBuffer& dst, const void* data, size_t bytes, size_t dstOffset = 0);
  void download(const DeviceBuffer& src, void* data, size_t bytes, size_t srcOffset = 0);

 private:
  void finishInit();
  VkCommandBuffer beginOnce();
  void endOnce(VkCommandBuffer cmd);

  bool ownsDevice_ = true;
  VkInstance instance_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t family_ = 0;
  std::string name_;
  uint32_t timestampValidBits_ = 0;
  double timestampPeriod_ = 1.0;
  VkPhysicalDeviceLimits limits_{};
  VkPhysicalDeviceMemoryProperties memory_{};
  VkCommandPool oncePool_ = VK_NULL_HANDLE;
  VkFence onceFence_ = VK_NULL_HANDLE;
  std::map<std::string, Pipeline> pipelines_;
  std::unique_ptr<DeviceBuffer> dummy_;
  friend class DeviceBuffer;
  std::atomic<uint64_t> liveBytes_{0};
};

/// Descriptor sets for (pipeline, bindings) combinations, written once and reused: a denoiser's
/// buffers are fixed between resizes, so steady-state frames write no descriptors.
class DescriptorCache {
 public:
  explicit DescriptorCache(Context& ctx) : ctx_(ctx) {}
  ~DescriptorCache();
  /// The set for these bindings, written on first use. `rewrite` writes it again: for buffers
  /// the application owns, which it may destroy and recreate under the same handle value.
  VkDescriptorSet get(const Pipeline& p, const std::vector<Binding>& bindings, bool rewrite = false);
  /// Frees every set (call only when the GPU no longer uses them, e.g. after a resize's wait).
  void clear();

 private:
  void addPool();
  void write(VkDescriptorSet set, const Pipeline& p, const std::vector<Binding>& bindings);
  Context& ctx_;
  std::vector<VkDescriptorPool> pools_;
  std::map<std::pair<VkDescriptorSetLayout, std::vector<Binding>>, VkDescriptorSet> sets_;
};

/// Records compute passes into a command buffer: dispatches over a width x height grid with a
/// full compute barrier between them, and a timestamp at every pass boundary.
class Recorder {
 public:
  Recorder(Context& ctx, DescriptorCache& cache, VkCommandBuffer cmd, VkQueryPool timestamps, uint32_t maxQueries)
      : ctx_(ctx), cache_(cache), cmd_(cmd), queries_(timestamps), maxQueries_(maxQueries) {}

  /// Dispatches shader `name` with one invocation per pixel of a width x height grid (rounded up
  /// to the shader's workgroup size; shaders return early outside the image).
  template <class PC>
  void dispatch(const std::string& name, const std::vector<Binding>& bindings, const PC& pushConstants, int width,
                int height) {
    static_assert(sizeof(PC) <= 128, "push constants are limited to 128 bytes");
    dispatchRaw(name, bindings, &pushConstants, sizeof(PC), width, height);
  }
  void dispatchRaw(const std::string& name, const std::vector<Binding>& bindings, const void* pc, uint32_t pcSize,
                   int width, int height);
  /// Makes every previous compute/transfer write visible to later compute and transfer work.
  void barrier();
  void fill(const DeviceBuffer& b, uint32_t value);
  void copy(const DeviceBuffer& src, const DeviceBuffer& dst, VkDeviceSize bytes, VkDeviceSize srcOffset = 0,
            VkDeviceSize dstOffset = 0);
  /// Marks a buffer as the application's: descriptor sets that bind it are rewritten at every
  /// dispatch rather than reused from the cache (its handle value may be recycled).
  void external(VkBuffer b) { external_.push_back(b); }
  void external(VkImageView v) { externalViews_.push_back(v); }
  /// Starts a named pass (ends the previous one): per-pass GPU times come from these marks.
  void pass(const std::string& name);
  /// Ends the last pass.
  void endPasses();
  VkCommandBuffer commandBuffer() const { return cmd_; }
  Context& context() { return ctx_; }
  /// Pass names in order; pass k spans timestamps k and k+1.
  const std::vector<std::string>& passNames() const { return names_; }
  uint32_t queriesWritten() const { return written_; }

 private:
  void mark();
  Context& ctx_;
  std::vector<VkBuffer> external_;
  std::vector<VkImageView> externalViews_;
  DescriptorCache& cache_;
  VkCommandBuffer cmd_;
  VkQueryPool queries_;
  uint32_t maxQueries_;
  uint32_t written_ = 0;
  bool pendingBarrier_ = false;
  std::vector<std::string> names_;
};

/// Workgroups needed to cover n invocations.
inline uint32_t groups(int n, uint32_t local) { return (uint32_t(n) + local - 1) / local; }

}  // namespace rtd::vk
