#include "backend/vulkan/context.h"

#include <algorithm>
#include <cctype>
#include <cstring>

#include "backend/vulkan/shaders.h"
#include "rtd/error.h"

namespace rtd::vk {

const char* resultName(VkResult r) {
  switch (r) {
    case VK_SUCCESS: return "VK_SUCCESS";
    case VK_NOT_READY: return "VK_NOT_READY";
    case VK_TIMEOUT: return "VK_TIMEOUT";
    case VK_ERROR_OUT_OF_HOST_MEMORY: return "VK_ERROR_OUT_OF_HOST_MEMORY";
    case VK_ERROR_OUT_OF_DEVICE_MEMORY: return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
    case VK_ERROR_INITIALIZATION_FAILED: return "VK_ERROR_INITIALIZATION_FAILED";
    case VK_ERROR_DEVICE_LOST: return "VK_ERROR_DEVICE_LOST";
    case VK_ERROR_MEMORY_MAP_FAILED: return "VK_ERROR_MEMORY_MAP_FAILED";
    case VK_ERROR_LAYER_NOT_PRESENT: return "VK_ERROR_LAYER_NOT_PRESENT";
    case VK_ERROR_EXTENSION_NOT_PRESENT: return "VK_ERROR_EXTENSION_NOT_PRESENT";
    case VK_ERROR_FEATURE_NOT_PRESENT: return "VK_ERROR_FEATURE_NOT_PRESENT";
    case VK_ERROR_INCOMPATIBLE_DRIVER: return "VK_ERROR_INCOMPATIBLE_DRIVER";
    case VK_ERROR_TOO_MANY_OBJECTS: return "VK_ERROR_TOO_MANY_OBJECTS";
    case VK_ERROR_OUT_OF_POOL_MEMORY: return "VK_ERROR_OUT_OF_POOL_MEMORY";
    case VK_ERROR_FRAGMENTED_POOL: return "VK_ERROR_FRAGMENTED_POOL";
    default: return "VkResult error";
  }
}

void check(VkResult r, const char* what) {
  if (r != VK_SUCCESS) throw Error(std::string("Vulkan: ") + what + " failed (" + resultName(r) + ")");
}

namespace {

constexpr uint32_t kApiVersion = VK_API_VERSION_1_2;
constexpr uint32_t kPushConstantBytes = 128;

const char* typeName(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU (software)";
    default: return "other";
  }
}

int typeRank(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
    default: return 4;
  }
}

const char* kNoDriver =
    "no Vulkan device available: the Vulkan loader found no driver (install one; on Debian, "
    "mesa-vulkan-drivers provides the lavapipe CPU device) — use --backend cpu meanwhile";

VkInstance createInstance(bool validation) {
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "rtdenoise";
  app.pEngineName = "rtdenoise";
  app.apiVersion = kApiVersion;
  std::vector<const char*> layers;
  if (validation) {
    uint32_t n = 0;
    vkEnumerateInstanceLayerProperties(&n, nullptr);
    std::vector<VkLayerProperties> props(n);
    vkEnumerateInstanceLayerProperties(&n, props.data());
    for (const auto& p : props)
      if (std::strcmp(p.layerName, "VK_LAYER_KHRONOS_validation") == 0) layers.push_back("VK_LAYER_KHRONOS_validation");
  }
  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  info.pApplicationInfo = &app;
  info.enabledLayerCount = uint32_t(layers.size());
  info.ppEnabledLayerNames = layers.data();
  VkInstance instance = VK_NULL_HANDLE;
  VkResult r = vkCreateInstance(&info, nullptr, &instance);
  if (r == VK_ERROR_INCOMPATIBLE_DRIVER || r == VK_ERROR_INITIALIZATION_FAILED) throw Error(kNoDriver);
  check(r, "vkCreateInstance");
  return instance;
}

int computeFamily(VkPhysicalDevice pd) {
  uint32_t n = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, nullptr);
  std::vector<VkQueueFamilyProperties> fams(n);
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, fams.data());
  int best = -1;
  for (uint32_t i = 0; i < n; ++i) {
    if (!(fams[i].queueFlags & VK_QUEUE_COMPUTE_BIT)) continue;
    // Prefer a family with timestamps (per-pass timings); any compute family works otherwise.
    if (best < 0 || (fams[best].timestampValidBits == 0 && fams[i].timestampValidBits > 0)) best = int(i);
  }
  return best;
}

// Usable devices (Vulkan 1.2+, a compute queue), in enumeration order.
std::vector<VkPhysicalDevice> usableDevices(VkInstance instance) {
  uint32_t n = 0;
  VkResult r = vkEnumeratePhysicalDevices(instance, &n, nullptr);
  if (r == VK_ERROR_INITIALIZATION_FAILED || n == 0) return {};
  check(r, "vkEnumeratePhysicalDevices");
  std::vector<VkPhysicalDevice> all(n);
  check(vkEnumeratePhysicalDevices(instance, &n, all.data()), "vkEnumeratePhysicalDevices");
  std::vector<VkPhysicalDevice> out;
  for (auto pd : all) {
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(pd, &p);
    if (p.apiVersion >= kApiVersion && computeFamily(pd) >= 0) out.push_back(pd);
  }
  return out;
}

PhysicalDeviceInfo describe(VkPhysicalDevice pd, int index) {
  VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  VkPhysicalDeviceProperties2 p{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  p.pNext = &driver;
  vkGetPhysicalDeviceProperties2(pd, &p);
  PhysicalDeviceInfo info;
  info.index = index;
  info.name = p.properties.deviceName;
  info.type = typeName(p.properties.deviceType);
  info.driver = std::string(driver.driverName) + (driver.driverInfo[0] ? std::string(" ") + driver.driverInfo : "");
  info.apiVersion = p.properties.apiVersion;
  return info;
}

std::string lower(std::string s) {
  for (auto& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string listing(const std::vector<VkPhysicalDevice>& devices) {
  std::string s;
  for (size_t i = 0; i < devices.size(); ++i)
    s += (i ? ", " : "") + std::to_string(i) + ": " + describe(devices[i], int(i)).name;
  return s.empty() ? "none" : s;
}

VkPhysicalDevice select(const std::vector<VkPhysicalDevice>& devices, const std::string& selector) {
  if (devices.empty()) throw Error(kNoDriver);
  if (selector.empty()) {
    auto rank = [](VkPhysicalDevice pd) {
      VkPhysicalDeviceProperties p;
      vkGetPhysicalDeviceProperties(pd, &p);
      return typeRank(p.deviceType);
    };
    return *std::min_element(devices.begin(), devices.end(),
                             [&](auto a, auto b) { return rank(a) < rank(b); });
  }
  const bool isIndex = std::all_of(selector.begin(), selector.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); });
  if (isIndex) {
    const size_t i = std::stoul(selector);
    if (i < devices.size()) return devices[i];
  } else {
    for (auto pd : devices)
      if (lower(describe(pd, 0).name).find(lower(selector)) != std::string::npos) return pd;
  }
  throw Error("no Vulkan device matches '" + selector + "' (devices: " + listing(devices) + ")");
}

void reflect(const EmbeddedShader& s, Pipeline& p) {
  // Scan the SPIR-V for Binding decorations, the variables they decorate and their types, and
  // the LocalSize execution mode, so the C++ side needs no hand-kept table of bindings per
  // shader. A binding is a storage buffer unless its variable is an image: OpTypeImage with
  // Sampled = 1 (texture2D, read with texelFetch) or 2 (image2D, a storage image).
  std::map<uint32_t, uint32_t> bindingOf;        // variable id -> binding
  std::map<uint32_t, uint32_t> pointee;          // pointer type id -> pointed-to type id
  std::map<uint32_t, VkDescriptorType> imageType;  // image type id -> descriptor type
  std::map<uint32_t, uint32_t> variableType;     // variable id -> pointer type id
  for (size_t i = 5; i < s.words;) {
    const uint32_t op = s.code[i] & 0xffffu, len = s.code[i] >> 16;
    if (len == 0) break;
    if (op == 71 /*OpDecorate*/ && len >= 4 && s.code[i + 2] == 33 /*Binding*/) bindingOf[s.code[i + 1]] = s.code[i + 3];
    if (op == 32 /*OpTypePointer*/ && len >= 4) pointee[s.code[i + 1]] = s.code[i + 3];
    if (op == 25 /*OpTypeImage*/ && len >= 9)
      imageType[s.code[i + 1]] = s.code[i + 7] == 2 ? VK_DESCRIPTOR_TYPE_STORAGE_IMAGE : VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE;
    if (op == 59 /*OpVariable*/ && len >= 4) variableType[s.code[i + 2]] = s.code[i + 1];
    if (op == 16 /*OpExecutionMode*/ && len >= 6 && s.code[i + 2] == 17 /*LocalSize*/)
      for (int k = 0; k < 3; ++k) p.localSize[k] = s.code[i + 3 + k];
    i += len;
  }
  p.bindings = 0;
  for (const auto& [variable, binding] : bindingOf) p.bindings = std::max(p.bindings, binding + 1);
  p.types.assign(p.bindings, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
  for (const auto& [variable, binding] : bindingOf) {
    auto v = variableType.find(variable);
    if (v == variableType.end()) continue;
    auto t = pointee.find(v->second);
    if (t == pointee.end()) continue;
    if (auto im = imageType.find(t->second); im != imageType.end()) p.types[binding] = im->second;
  }
}

}  // namespace

std::vector<PhysicalDeviceInfo> enumeratePhysicalDevices() {
  VkInstance instance = createInstance(false);
  std::vector<PhysicalDeviceInfo> out;
  try {
    auto devices = usableDevices(instance);
    for (size_t i = 0; i < devices.size(); ++i) out.push_back(describe(devices[i], int(i)));
  } catch (...) {
    vkDestroyInstance(instance, nullptr);
    throw;
  }
  vkDestroyInstance(instance, nullptr);
  if (out.empty()) throw Error(kNoDriver);
  return out;
}

// ---- DeviceBuffer ---------------------------------------------------------------------------------

namespace {
thread_local std::shared_ptr<MemoryTally> currentOwner;  // MemoryOwnerScope's
}  // namespace

MemoryOwnerScope::MemoryOwnerScope(std::shared_ptr<MemoryTally> owner) : previous_(std::move(currentOwner)) {
  currentOwner = std::move(owner);
}
MemoryOwnerScope::~MemoryOwnerScope() { currentOwner = std::move(previous_); }

DeviceBuffer::DeviceBuffer(Context& ctx, VkDeviceSize size, bool hostVisible) : ctx_(&ctx), size_(size) {
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = std::max<VkDeviceSize>(size, 4);
  info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  check(vkCreateBuffer(ctx.device(), &info, nullptr, &buffer_), "vkCreateBuffer");
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(ctx.device(), buffer_, &req);
  VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  alloc.allocationSize = req.size;
  alloc.memoryTypeIndex = ctx.memoryType(req.memoryTypeBits, hostVisible);
  VkResult r = vkAllocateMemory(ctx.device(), &alloc, nullptr, &memory_);
  if (r != VK_SUCCESS) {
    vkDestroyBuffer(ctx.device(), buffer_, nullptr);
    buffer_ = VK_NULL_HANDLE;
    check(r, ("vkAllocateMemory of " + std::to_string(size >> 20) + " MiB").c_str());
  }
  check(vkBindBufferMemory(ctx.device(), buffer_, memory_, 0), "vkBindBufferMemory");
  if (hostVisible) check(vkMapMemory(ctx.device(), memory_, 0, VK_WHOLE_SIZE, 0, &mapped_), "vkMapMemory");
  allocated_ = req.size;
  hostVisible_ = hostVisible;
  ctx.liveBytes_ += allocated_;
  owner_ = currentOwner;
  if (owner_) (hostVisible ? owner_->hostVisible : owner_->deviceLocal) += allocated_;
}

DeviceBuffer& DeviceBuffer::operator=(DeviceBuffer&& o) noexcept {
  if (this != &o) {
    release();
    std::swap(ctx_, o.ctx_);
    std::swap(buffer_, o.buffer_);
    std::swap(memory_, o.memory_);
    std::swap(size_, o.size_);
    std::swap(mapped_, o.mapped_);
    std::swap(allocated_, o.allocated_);
    std::swap(hostVisible_, o.hostVisible_);
    std::swap(owner_, o.owner_);
  }
  return *this;
}

void DeviceBuffer::release() {
  if (!ctx_) return;
  if (buffer_) vkDestroyBuffer(ctx_->device(), buffer_, nullptr);
  if (memory_) vkFreeMemory(ctx_->device(), memory_, nullptr);
  ctx_->liveBytes_ -= allocated_;
  if (owner_) (hostVisible_ ? owner_->hostVisible : owner_->deviceLocal) -= allocated_;
  owner_.reset();
  buffer_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
  mapped_ = nullptr;
  size_ = allocated_ = 0;
}

void Planes::allocate(Context& ctx, int w, int h, int n) {
  width = w;
  height = h;
  count = n;
  buffer = DeviceBuffer(ctx, VkDeviceSize(w) * h * n * 4, false);
}

// ---- Context --------------------------------------------------------------------------------

Context::Context(const DeviceDesc& desc) {
  instance_ = createInstance(desc.vulkanValidation);
  try {
    physical_ = select(usableDevices(instance_), desc.vulkanDevice);
    family_ = uint32_t(computeFamily(physical_));
    const float priority = 1.0f;
    VkDeviceQueueCreateInfo q{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    q.queueFamilyIndex = family_;
    q.queueCount = 1;
    q.pQueuePriorities = &priority;
    VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    info.queueCreateInfoCount = 1;
    info.pQueueCreateInfos = &q;
    check(vkCreateDevice(physical_, &info, nullptr, &device_), "vkCreateDevice");
    vkGetDeviceQueue(device_, family_, 0, &queue_);
    finishInit();
  } catch (...) {
    if (device_) vkDestroyDevice(device_, nullptr);
    vkDestroyInstance(instance_, nullptr);
    throw;
  }
}

Context::Context(const VulkanDeviceDesc& h) : ownsDevice_(false) {
  if (!h.physicalDevice || !h.device || !h.queue) throw Error("Vulkan: external device needs physicalDevice, device and queue");
  instance_ = h.instance;
  physical_ = h.physicalDevice;
  device_ = h.device;
  queue_ = h.queue;
  family_ = h.queueFamily;
  finishInit();
}

void Context::finishInit() {
  VkPhysicalDeviceProperties p;
  vkGetPhysicalDeviceProperties(physical_, &p);
  name_ = p.deviceName;
  limits_ = p.limits;
  timestampPeriod_ = p.limits.timestampPeriod;
  uint32_t n = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(physical_, &n, nullptr);
  std::vector<VkQueueFamilyProperties> fams(n);
  vkGetPhysicalDeviceQueueFamilyProperties(physical_, &n, fams.data());
  if (family_ >= n || !(fams[family_].queueFlags & VK_QUEUE_COMPUTE_BIT))
    throw Error("Vulkan: queue family " + std::to_string(family_) + " of '" + name_ + "' has no compute support");
  timestampValidBits_ = fams[family_].timestampValidBits;
  vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);

  VkCommandPoolCreateInfo pool{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT | VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
  pool.queueFamilyIndex = family_;
  check(vkCreateCommandPool(device_, &pool, nullptr, &oncePool_), "vkCreateCommandPool");
  VkFenceCreateInfo fence{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  check(vkCreateFence(device_, &fence, nullptr, &onceFence_), "vkCreateFence");
  dummy_ = std::make_unique<DeviceBuffer>(*this, 16, false);
}

Context::~Context() {
  if (!device_) return;
  vkDeviceWaitIdle(device_);
  dummy_.reset();
  for (auto& [name, p] : pipelines_) {
    vkDestroyPipeline(device_, p.pipeline, nullptr);
    vkDestroyPipelineLayout(device_, p.layout, nullptr);
    vkDestroyDescriptorSetLayout(device_, p.setLayout, nullptr);
    vkDestroyShaderModule(device_, p.module, nullptr);
  }
  if (onceFence_) vkDestroyFence(device_, onceFence_, nullptr);
  if (oncePool_) vkDestroyCommandPool(device_, oncePool_, nullptr);
  if (ownsDevice_) {
    vkDestroyDevice(device_, nullptr);
    vkDestroyInstance(instance_, nullptr);
  }
}

uint32_t Context::memoryType(uint32_t typeBits, bool hostVisible) const {
  const VkMemoryPropertyFlags want = hostVisible ? VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT
                                                 : VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
  // Host-visible: prefer cached memory (read-backs); device-local: any.
  int fallback = -1;
  for (uint32_t i = 0; i < memory_.memoryTypeCount; ++i) {
    if (!(typeBits & (1u << i)) || (memory_.memoryTypes[i].propertyFlags & want) != want) continue;
    if (!hostVisible || (memory_.memoryTypes[i].propertyFlags & VK_MEMORY_PROPERTY_HOST_CACHED_BIT)) return i;
    if (fallback < 0) fallback = int(i);
  }
  if (fallback >= 0) return uint32_t(fallback);
  if (!hostVisible)  // no device-local type for this resource: any type that fits
    for (uint32_t i = 0; i < memory_.memoryTypeCount; ++i)
      if (typeBits & (1u << i)) return i;
  throw Error("Vulkan: no suitable memory type on '" + name_ + "'");
}

const Pipeline& Context::pipeline(const std::string& name) {
  if (auto it = pipelines_.find(name); it != pipelines_.end()) return it->second;
  const EmbeddedShader* shader = nullptr;
  for (const auto& s : embeddedShaders())
    if (name == s.name) shader = &s;
  if (!shader) throw Error("Vulkan: no embedded shader named '" + name + "'");
  Pipeline p;
  reflect(*shader, p);

  VkShaderModuleCreateInfo mi{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  mi.codeSize = shader->words * 4;
  mi.pCode = shader->code;
  check(vkCreateShaderModule(device_, &mi, nullptr, &p.module), "vkCreateShaderModule");

  std::vector<VkDescriptorSetLayoutBinding> b(p.bindings);
  for (uint32_t i = 0; i < p.bindings; ++i)
    b[i] = {i, p.types[i], 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
  VkDescriptorSetLayoutCreateInfo li{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  li.bindingCount = p.bindings;
  li.pBindings = b.data();
  check(vkCreateDescriptorSetLayout(device_, &li, nullptr, &p.setLayout), "vkCreateDescriptorSetLayout");

  VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, kPushConstantBytes};
  VkPipelineLayoutCreateInfo pl{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  pl.setLayoutCount = 1;
  pl.pSetLayouts = &p.setLayout;
  pl.pushConstantRangeCount = 1;
  pl.pPushConstantRanges = &range;
  check(vkCreatePipelineLayout(device_, &pl, nullptr, &p.layout), "vkCreatePipelineLayout");

  VkComputePipelineCreateInfo ci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  ci.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  ci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  ci.stage.module = p.module;
  ci.stage.pName = "main";
  ci.layout = p.layout;
  check(vkCreateComputePipelines(device_, VK_NULL_HANDLE, 1, &ci, nullptr, &p.pipeline),
        ("vkCreateComputePipelines(" + name + ")").c_str());
  return pipelines_.emplace(name, p).first->second;
}

VkCommandBuffer Context::beginOnce() {
  VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = oncePool_;
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = 1;
  VkCommandBuffer cmd;
  check(vkAllocateCommandBuffers(device_, &ai, &cmd), "vkAllocateCommandBuffers");
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(cmd, &bi), "vkBeginCommandBuffer");
  return cmd;
}

void Context::endOnce(VkCommandBuffer cmd) {
  check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmd;
  check(vkQueueSubmit(queue_, 1, &si, onceFence_), "vkQueueSubmit");
  VkResult r = vkWaitForFences(device_, 1, &onceFence_, VK_TRUE, UINT64_MAX);
  vkResetFences(device_, 1, &onceFence_);
  vkFreeCommandBuffers(device_, oncePool_, 1, &cmd);
  check(r, "vkWaitForFences");
}

void Context::upload(const DeviceBuffer& dst, const void* data, size_t bytes, size_t dstOffset) {
  if (dst.mapped()) {
    std::memcpy(static_cast<char*>(dst.mapped()) + dstOffset, data, bytes);
    return;
  }
  DeviceBuffer staging(*this, bytes, true);
  std::memcpy(staging.mapped(), data, bytes);
  runOnce([&](VkCommandBuffer cmd) {
    VkBufferCopy c{0, dstOffset, bytes};
    vkCmdCopyBuffer(cmd, staging.handle(), dst.handle(), 1, &c);
  });
}

void Context::download(const DeviceBuffer& src, void* data, size_t bytes, size_t srcOffset) {
  if (src.mapped()) {
    std::memcpy(data, static_cast<const char*>(src.mapped()) + srcOffset, bytes);
    return;
  }
  DeviceBuffer staging(*this, bytes, true);
  runOnce([&](VkCommandBuffer cmd) {
    VkBufferCopy c{srcOffset, 0, bytes};
    vkCmdCopyBuffer(cmd, src.handle(), staging.handle(), 1, &c);
  });
  std::memcpy(data, staging.mapped(), bytes);
}

// ---- DescriptorCache ------------------------------------------------------------------------

DescriptorCache::~DescriptorCache() {
  for (auto p : pools_) vkDestroyDescriptorPool(ctx_.device(), p, nullptr);
}

void DescriptorCache::addPool() {
  const VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 4096},
                                        {VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, 256},
                                        {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 64}};
  VkDescriptorPoolCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  info.maxSets = 512;
  info.poolSizeCount = 3;
  info.pPoolSizes = sizes;
  VkDescriptorPool pool;
  check(vkCreateDescriptorPool(ctx_.device(), &info, nullptr, &pool), "vkCreateDescriptorPool");
  pools_.push_back(pool);
}

void DescriptorCache::clear() {
  for (auto p : pools_) vkDestroyDescriptorPool(ctx_.device(), p, nullptr);
  pools_.clear();
  sets_.clear();
}

VkDescriptorSet DescriptorCache::get(const Pipeline& p, const std::vector<Binding>& bindings, bool rewrite) {
  if (bindings.size() != p.bindings)
    throw Error("Vulkan: internal error: shader expects " + std::to_string(p.bindings) + " bindings, got " +
                std::to_string(bindings.size()));
  auto key = std::make_pair(p.setLayout, bindings);
  if (auto it = sets_.find(key); it != sets_.end()) {
    if (rewrite) write(it->second, p, bindings);
    return it->second;
  }
  if (pools_.empty()) addPool();
  VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  ai.descriptorSetCount = 1;
  ai.pSetLayouts = &p.setLayout;
  VkDescriptorSet set = VK_NULL_HANDLE;
  ai.descriptorPool = pools_.back();
  VkResult r = vkAllocateDescriptorSets(ctx_.device(), &ai, &set);
  if (r == VK_ERROR_OUT_OF_POOL_MEMORY || r == VK_ERROR_FRAGMENTED_POOL) {
    addPool();
    ai.descriptorPool = pools_.back();
    r = vkAllocateDescriptorSets(ctx_.device(), &ai, &set);
  }
  check(r, "vkAllocateDescriptorSets");
  write(set, p, bindings);
  sets_.emplace(std::move(key), set);
  return set;
}

void DescriptorCache::write(VkDescriptorSet set, const Pipeline& p, const std::vector<Binding>& bindings) {
  std::vector<VkDescriptorBufferInfo> infos(bindings.size());
  std::vector<VkDescriptorImageInfo> images(bindings.size());
  std::vector<VkWriteDescriptorSet> writes(bindings.size());
  for (size_t i = 0; i < bindings.size(); ++i) {
    const VkDescriptorType type = p.types[i];
    const bool image = type != VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    if (image != (bindings[i].view != VK_NULL_HANDLE))
      throw Error("Vulkan: internal error: binding " + std::to_string(i) + (image ? " needs an image view" : " needs a buffer"));
    infos[i] = {bindings[i].buffer, bindings[i].offset, bindings[i].range};
    images[i] = {VK_NULL_HANDLE, bindings[i].view, bindings[i].layout};
    writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    writes[i].dstSet = set;
    writes[i].dstBinding = uint32_t(i);
    writes[i].descriptorCount = 1;
    writes[i].descriptorType = type;
    if (image) writes[i].pImageInfo = &images[i];
    else writes[i].pBufferInfo = &infos[i];
  }
  vkUpdateDescriptorSets(ctx_.device(), uint32_t(writes.size()), writes.data(), 0, nullptr);
}

// ---- Recorder -------------------------------------------------------------------------------

void Recorder::barrier() {
  VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  mb.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT |
                     VK_ACCESS_TRANSFER_WRITE_BIT;
  vkCmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &mb, 0, nullptr, 0,
                       nullptr);
  pendingBarrier_ = false;
}

void Recorder::dispatchRaw(const std::string& name, const std::vector<Binding>& bindings, const void* pc,
                           uint32_t pcSize, int width, int height) {
  const Pipeline& p = ctx_.pipeline(name);
  bool rewrite = false;
  for (const Binding& b : bindings)
    rewrite |= b.view ? std::find(externalViews_.begin(), externalViews_.end(), b.view) != externalViews_.end()
                      : std::find(external_.begin(), external_.end(), b.buffer) != external_.end();
  VkDescriptorSet set = cache_.get(p, bindings, rewrite);
  if (pendingBarrier_) barrier();
  vkCmdBindPipeline(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, p.pipeline);
  vkCmdBindDescriptorSets(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, p.layout, 0, 1, &set, 0, nullptr);
  if (pcSize) vkCmdPushConstants(cmd_, p.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, pcSize, pc);
  vkCmdDispatch(cmd_, groups(width, p.localSize[0]), groups(height, p.localSize[1]), 1);
  pendingBarrier_ = true;
}

void Recorder::fill(const DeviceBuffer& b, uint32_t value) {
  if (pendingBarrier_) barrier();
  vkCmdFillBuffer(cmd_, b.handle(), 0, VK_WHOLE_SIZE, value);
  pendingBarrier_ = true;
}

void Recorder::copy(const DeviceBuffer& src, const DeviceBuffer& dst, VkDeviceSize bytes, VkDeviceSize srcOffset,
                    VkDeviceSize dstOffset) {
  if (pendingBarrier_) barrier();
  VkBufferCopy c{srcOffset, dstOffset, bytes};
  vkCmdCopyBuffer(cmd_, src.handle(), dst.handle(), 1, &c);
  pendingBarrier_ = true;
}

void Recorder::mark() {
  if (!queries_ || written_ >= maxQueries_) return;
  vkCmdWriteTimestamp(cmd_, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, written_++);
}

void Recorder::pass(const std::string& name) {
  mark();  // the end of the previous pass is the start of this one
  names_.push_back(name);
}

void Recorder::endPasses() {
  if (!names_.empty()) mark();
}

}  // namespace rtd::vk
