// The C API (rtd/capi.h) over the C++ API: handles wrap rtd::Device and rtd::Denoiser, every
// entry point catches what the C++ side throws and turns it into an RTDError, kept by the device
// and reported to its callback. Nothing here reaches past the public C++ headers.
#include "rtd/capi.h"

#include <atomic>
#include <cmath>
#include <memory>
#include <mutex>
#include <new>
#include <sstream>
#include <string>
#include <vector>

#include "rtd/rtd.h"

static_assert(int(rtd::Format::Half4) == RTD_FORMAT_HALF4 && int(rtd::Format::Int32) == RTD_FORMAT_INT32 &&
                  int(rtd::Format::Float3) == RTD_FORMAT_FLOAT3,
              "RTDFormat mirrors rtd::Format");

namespace {

// A failure with the code the C side reports; thrown inside the entry points only.
struct CError {
  RTDError code;
  std::string message;
};

}  // namespace

// Outside the anonymous namespace: RTDDeviceImpl, which the C header declares, holds one.
namespace rtd::capi {

// The first unqueried error and the message last handed out (which must outlive the query).
struct ErrorState {
  RTDError code = RTD_ERROR_NONE;
  std::string message, returned;

  void store(RTDError c, const std::string& m) {
    if (code != RTD_ERROR_NONE) return;  // the first error is the one reported
    code = c;
    message = m;
  }
  RTDError take(const char** out) {
    const RTDError c = code;
    returned = std::move(message);
    message.clear();
    code = RTD_ERROR_NONE;
    if (out) *out = c == RTD_ERROR_NONE ? nullptr : returned.c_str();
    return c;
  }
};

}  // namespace rtd::capi

namespace {
using rtd::capi::ErrorState;

// Errors of calls without a device to report to (a null handle, rtdNewDevice, the lists).
thread_local ErrorState threadErrors;

}  // namespace

struct RTDDeviceImpl {
  std::atomic<int> refs{1};
  rtd::DeviceDesc desc;
  std::unique_ptr<rtd::Device> device;  // set by rtdCommitDevice
  std::string name;
  std::mutex mutex;  // guards the error state and the callback
  ErrorState errors;
  RTDErrorFunction callback = nullptr;
  void* callbackUser = nullptr;

  void report(RTDError code, const std::string& message) {
    RTDErrorFunction fn;
    void* user;
    {
      std::lock_guard lock(mutex);
      errors.store(code, message);
      fn = callback;
      user = callbackUser;
    }
    if (fn) fn(user, code, message.c_str());
  }
};

struct RTDDenoiserImpl {
  std::atomic<int> refs{1};
  RTDDeviceImpl* device;  // retained
  std::unique_ptr<rtd::Denoiser> denoiser;
  rtd::FrameInputs frame;
  rtd::ImageView output;
  std::string text;  // the last string returned
  std::vector<rtd::SettingInfo> settings;
};

namespace {

void retain(RTDDeviceImpl* d) { d->refs.fetch_add(1, std::memory_order_relaxed); }
void release(RTDDeviceImpl* d) {
  if (d->refs.fetch_sub(1, std::memory_order_acq_rel) == 1) delete d;
}

// Runs `body` and turns whatever it throws into the returned RTDError, reported to `device`
// (or to the thread when null). rtd::Error means bad input unless `rtdErrorCode` says otherwise.
template <class F> RTDError guarded(RTDDeviceImpl* device, F&& body, RTDError rtdErrorCode = RTD_ERROR_INVALID_ARGUMENT) {
  RTDError code;
  std::string message;
  try {
    body();
    return RTD_ERROR_NONE;
  } catch (const CError& e) {
    code = e.code;
    message = e.message;
  } catch (const rtd::Error& e) {
    // The C++ API reports what escaped it from below (the standard library, oneTBB, a driver)
    // as rtd::Error("<call>: internal error: ...") (src/core/api_guard.h): not bad input.
    message = e.what();
    code = message.find(": internal error: ") != std::string::npos ? RTD_ERROR_UNKNOWN : rtdErrorCode;
  } catch (const std::bad_alloc&) {
    code = RTD_ERROR_OUT_OF_MEMORY;
    message = "out of memory";
  } catch (const std::exception& e) {
    code = RTD_ERROR_UNKNOWN;
    message = std::string("internal error: ") + e.what();
  } catch (...) {
    code = RTD_ERROR_UNKNOWN;
    message = "internal error";
  }
  if (device) device->report(code, message);
  else threadErrors.store(code, message);
  return code;
}

[[noreturn]] void fail(RTDError code, std::string message) { throw CError{code, std::move(message)}; }

void requireName(const char* name, const char* what) {
  if (!name) fail(RTD_ERROR_INVALID_ARGUMENT, std::string(what) + " is NULL");
}

RTDDeviceImpl* deviceOf(RTDDenoiser d) { return d ? d->device : nullptr; }
void requireDenoiser(RTDDenoiser d) {
  if (!d) fail(RTD_ERROR_INVALID_ARGUMENT, "denoiser is NULL");
}

// The committed rtd::Device of a handle.
rtd::Device& committed(RTDDevice d) {
  if (!d) fail(RTD_ERROR_INVALID_ARGUMENT, "device is NULL");
  if (!d->device) fail(RTD_ERROR_INVALID_OPERATION, "device not committed (call rtdCommitDevice first)");
  return *d->device;
}

void requireUncommitted(RTDDevice d) {
  if (!d) fail(RTD_ERROR_INVALID_ARGUMENT, "device is NULL");
  if (d->device) fail(RTD_ERROR_INVALID_OPERATION, "device already committed (parameters cannot change after rtdCommitDevice)");
}

std::vector<rtd::DeviceInfo>& physicalDevices() {
  thread_local std::vector<rtd::DeviceInfo> list;
  return list;
}

const char* methodField(int index, bool summary) {
  const char* out = nullptr;
  guarded(nullptr, [&] {
    static const std::vector<rtd::MethodInfo> methods = rtd::listMethods();
    if (index < 0 || index >= int(methods.size()))
      fail(RTD_ERROR_INVALID_ARGUMENT, "method index " + std::to_string(index) + " out of range");
    out = summary ? methods[index].summary.c_str() : methods[index].name.c_str();
  });
  return out;
}

// Pass `index` of the last frame (throws CError out of range).
const rtd::PassTiming& passAt(RTDDenoiser denoiser, int index) {
  requireDenoiser(denoiser);
  const auto& passes = denoiser->denoiser->stats().passes;
  if (index < 0 || index >= int(passes.size()))
    fail(RTD_ERROR_INVALID_ARGUMENT, "pass index " + std::to_string(index) + " out of range");
  return passes[size_t(index)];
}

const rtd::MemoryUse& memoryAt(RTDDenoiser denoiser, int index) {
  requireDenoiser(denoiser);
  const auto& memory = denoiser->denoiser->stats().memory;
  if (index < 0 || index >= int(memory.size()))
    fail(RTD_ERROR_INVALID_ARGUMENT, "memory category index " + std::to_string(index) + " out of range");
  return memory[size_t(index)];
}

std::string formatNumber(double v) {
  std::ostringstream s;
  s.precision(9);
  s << v;
  return s.str();
}

}  // namespace

extern "C" {

int rtdGetVersion(void) { return rtd::version(); }
const char* rtdGetVersionString(void) { return rtd::versionString(); }

int rtdGetMethodCount(void) { return int(rtd::listMethods().size()); }
const char* rtdGetMethodName(int index) { return methodField(index, false); }
const char* rtdGetMethodSummary(int index) { return methodField(index, true); }

int rtdGetPhysicalDeviceCount(void) {
  int n = 0;
  guarded(nullptr, [&] {
    physicalDevices() = rtd::listDevices();
    n = int(physicalDevices().size());
  });
  return n;
}

const char* rtdGetPhysicalDeviceName(int index) {
  const char* out = nullptr;
  guarded(nullptr, [&] {
    if (index < 0 || index >= int(physicalDevices().size()))
      fail(RTD_ERROR_INVALID_ARGUMENT, "physical device index " + std::to_string(index) +
                                           " out of range (call rtdGetPhysicalDeviceCount first)");
    out = physicalDevices()[index].name.c_str();
  });
  return out;
}

int rtdGetPhysicalDeviceBackend(int index) {
  int out = -1;
  guarded(nullptr, [&] {
    if (index < 0 || index >= int(physicalDevices().size()))
      fail(RTD_ERROR_INVALID_ARGUMENT, "physical device index " + std::to_string(index) + " out of range");
    out = physicalDevices()[index].backend == rtd::Backend::Cpu ? RTD_BACKEND_CPU : RTD_BACKEND_VULKAN;
  });
  return out;
}

RTDDevice rtdNewDevice(RTDBackend backend) {
  RTDDevice out = nullptr;
  guarded(nullptr, [&] {
    if (backend != RTD_BACKEND_CPU && backend != RTD_BACKEND_VULKAN)
      fail(RTD_ERROR_INVALID_ARGUMENT, "unknown backend " + std::to_string(int(backend)));
    out = new RTDDeviceImpl;
    out->desc.backend = backend == RTD_BACKEND_CPU ? rtd::Backend::Cpu : rtd::Backend::Vulkan;
  });
  return out;
}

RTDError rtdSetDeviceInt(RTDDevice device, const char* name, int value) {
  return guarded(device, [&] {
    requireUncommitted(device);
    requireName(name, "parameter name");
    const std::string n = name;
    if (n == "threads") {
      if (value < 0) fail(RTD_ERROR_INVALID_ARGUMENT, "device parameter 'threads' must be >= 0");
      device->desc.threads = value;
    } else if (n == "vulkanValidation") {
      device->desc.vulkanValidation = value != 0;
    } else {
      fail(RTD_ERROR_INVALID_ARGUMENT, "unknown device parameter '" + n + "' (threads, vulkanValidation)");
    }
  });
}

RTDError rtdSetDeviceString(RTDDevice device, const char* name, const char* value) {
  return guarded(device, [&] {
    requireUncommitted(device);
    requireName(name, "parameter name");
    requireName(value, "parameter value");
    if (std::string(name) != "vulkanDevice")
      fail(RTD_ERROR_INVALID_ARGUMENT, "unknown device parameter '" + std::string(name) + "' (vulkanDevice)");
    device->desc.vulkanDevice = value;
  });
}

RTDError rtdCommitDevice(RTDDevice device) {
  return guarded(
      device,
      [&] {
        requireUncommitted(device);
        device->device = rtd::Device::create(device->desc);
        device->name = device->device->name();
      },
      RTD_ERROR_UNSUPPORTED);
}

const char* rtdGetDeviceName(RTDDevice device) {
  const char* out = nullptr;
  guarded(device, [&] {
    committed(device);
    out = device->name.c_str();
  });
  return out;
}

void rtdSetDeviceErrorFunction(RTDDevice device, RTDErrorFunction func, void* userPtr) {
  guarded(nullptr, [&] {
    if (!device) fail(RTD_ERROR_INVALID_ARGUMENT, "device is NULL");
    std::lock_guard lock(device->mutex);
    device->callback = func;
    device->callbackUser = userPtr;
  });
}

RTDError rtdGetDeviceError(RTDDevice device, const char** message) {
  if (!device) return threadErrors.take(message);
  std::lock_guard lock(device->mutex);
  return device->errors.take(message);
}

void rtdRetainDevice(RTDDevice device) {
  if (device) retain(device);
}
void rtdReleaseDevice(RTDDevice device) {
  if (device) release(device);
}

RTDDenoiser rtdNewDenoiser(RTDDevice device, const char* method) {
  RTDDenoiser out = nullptr;
  guarded(device, [&] {
    rtd::Device& d = committed(device);
    requireName(method, "method");
    bool known = false, onBackend = false;
    for (const auto& m : rtd::listMethods())
      if (m.name == method) known = true, onBackend = d.backend() == rtd::Backend::Cpu ? m.cpu : m.vulkan;
    if (!known) fail(RTD_ERROR_INVALID_ARGUMENT, "unknown method '" + std::string(method) + "' (see rtdGetMethodName)");
    if (!onBackend)
      fail(RTD_ERROR_UNSUPPORTED, "method '" + std::string(method) + "' has no " +
                                      std::string(rtd::backendName(d.backend())) + " implementation");
    auto den = d.createDenoiser(method);
    out = new RTDDenoiserImpl{{1}, device, std::move(den), {}, {}, {}, {}};
    retain(device);
  });
  return out;
}

void rtdRetainDenoiser(RTDDenoiser denoiser) {
  if (denoiser) denoiser->refs.fetch_add(1, std::memory_order_relaxed);
}

void rtdReleaseDenoiser(RTDDenoiser denoiser) {
  if (!denoiser || denoiser->refs.fetch_sub(1, std::memory_order_acq_rel) != 1) return;
  RTDDeviceImpl* device = denoiser->device;
  delete denoiser;
  release(device);
}

RTDError rtdSetDenoiserSetting(RTDDenoiser denoiser, const char* name, const char* value) {
  return guarded(deviceOf(denoiser), [&] {
    requireDenoiser(denoiser);
    requireName(name, "setting name");
    requireName(value, "setting value");
    denoiser->denoiser->set(name, value);
  });
}

RTDError rtdSetDenoiserSettingFloat(RTDDenoiser denoiser, const char* name, float value) {
  return rtdSetDenoiserSetting(denoiser, name, formatNumber(value).c_str());  // "nan", "inf" are rejected
}
RTDError rtdSetDenoiserSettingInt(RTDDenoiser denoiser, const char* name, int value) {
  return rtdSetDenoiserSetting(denoiser, name, std::to_string(value).c_str());
}
RTDError rtdSetDenoiserSettingBool(RTDDenoiser denoiser, const char* name, int value) {
  return rtdSetDenoiserSetting(denoiser, name, value ? "true" : "false");
}

const char* rtdGetDenoiserSetting(RTDDenoiser denoiser, const char* name) {
  const char* out = nullptr;
  guarded(deviceOf(denoiser), [&] {
    requireDenoiser(denoiser);
    requireName(name, "setting name");
    for (const auto& s : denoiser->denoiser->settings())
      if (s.name == name) {
        denoiser->text = s.value;
        out = denoiser->text.c_str();
        return;
      }
    fail(RTD_ERROR_INVALID_ARGUMENT, "method '" + std::string(denoiser->denoiser->method()) + "' has no setting '" +
                                         std::string(name) + "'");
  });
  return out;
}

int rtdGetDenoiserSettingCount(RTDDenoiser denoiser) {
  int n = 0;
  guarded(deviceOf(denoiser), [&] {
    requireDenoiser(denoiser);
    denoiser->settings = denoiser->denoiser->settings();
    n = int(denoiser->settings.size());
  });
  return n;
}

const char* rtdGetDenoiserSettingName(RTDDenoiser denoiser, int index) {
  const char* out = nullptr;
  guarded(deviceOf(denoiser), [&] {
    requireDenoiser(denoiser);
    if (denoiser->settings.empty()) denoiser->settings = denoiser->denoiser->settings();
    if (index < 0 || index >= int(denoiser->settings.size()))
      fail(RTD_ERROR_INVALID_ARGUMENT, "setting index " + std::to_string(index) + " out of range");
    out = denoiser->settings[index].name.c_str();
  });
  return out;
}

const char* rtdGetDenoiserRequiredBuffers(RTDDenoiser denoiser) {
  const char* out = nullptr;
  guarded(deviceOf(denoiser), [&] {
    requireDenoiser(denoiser);
    denoiser->text.clear();
    for (rtd::Buffer b : denoiser->denoiser->requiredBuffers()) {
      if (!denoiser->text.empty()) denoiser->text += ',';
      denoiser->text += rtd::bufferName(b);
    }
    out = denoiser->text.c_str();
  });
  return out;
}

RTDError rtdSetDenoiserImage(RTDDenoiser denoiser, const char* buffer, const RTDImageView* view) {
  return guarded(deviceOf(denoiser), [&] {
    requireDenoiser(denoiser);
    requireName(buffer, "buffer name");
    const std::string name = buffer;
    rtd::ImageView* target = nullptr;
    if (name == "output") {
      target = &denoiser->output;
    } else if (auto b = rtd::bufferFromName(name)) {
      target = &denoiser->frame[*b];
    } else {
      fail(RTD_ERROR_INVALID_ARGUMENT, "unknown buffer '" + name + "' (names as rtd::Buffer: color, albedo, normal, ...; or output)");
    }
    if (!view || !view->data) {
      *target = {};
      return;
    }
    if (int(view->format) <= RTD_FORMAT_UNDEFINED || int(view->format) > RTD_FORMAT_HALF4)
      fail(RTD_ERROR_INVALID_ARGUMENT, "buffer '" + name + "': " + std::to_string(int(view->format)) + " is not an RTDFormat");
    if (view->width <= 0 || view->height <= 0)
      fail(RTD_ERROR_INVALID_ARGUMENT, "buffer '" + name + "': size " + std::to_string(view->width) + "x" +
                                           std::to_string(view->height) + " is not positive");
    *target = {view->data, view->width, view->height, rtd::Format(view->format), view->pixelStride, view->rowStride};
  });
}

RTDError rtdSetDenoiserCamera(RTDDenoiser denoiser, const float worldToCamera[16], const float projection[16]) {
  return guarded(deviceOf(denoiser), [&] {
    requireDenoiser(denoiser);
    rtd::Camera& c = denoiser->frame.camera;
    if (!worldToCamera && !projection) {
      c = {};
      return;
    }
    if (!worldToCamera || !projection) fail(RTD_ERROR_INVALID_ARGUMENT, "camera: give both matrices or neither");
    for (int k = 0; k < 16; ++k)
      if (!std::isfinite(worldToCamera[k]) || !std::isfinite(projection[k]))
        fail(RTD_ERROR_INVALID_ARGUMENT, "camera: matrices must be finite");
    std::copy(worldToCamera, worldToCamera + 16, c.worldToCamera.begin());
    std::copy(projection, projection + 16, c.projection.begin());
    c.valid = true;
  });
}

RTDError rtdSetDenoiserConvention(RTDDenoiser denoiser, const char* name, const char* value) {
  return guarded(deviceOf(denoiser), [&] {
    requireDenoiser(denoiser);
    requireName(name, "convention name");
    requireName(value, "convention value");
    rtd::setConvention(denoiser->frame.conventions, name, value);
  });
}

RTDError rtdSetDenoiserDepthProjection(RTDDenoiser denoiser, const float projection[16]) {
  return guarded(deviceOf(denoiser), [&] {
    requireDenoiser(denoiser);
    if (!projection) fail(RTD_ERROR_INVALID_ARGUMENT, "depth projection is NULL");
    std::copy(projection, projection + 16, denoiser->frame.conventions.depthProjection.begin());
  });
}

RTDError rtdDenoise(RTDDenoiser denoiser) {
  return guarded(deviceOf(denoiser), [&] {
    requireDenoiser(denoiser);
    if (denoiser->output.empty())
      fail(RTD_ERROR_INVALID_OPERATION, "no output image (rtdSetDenoiserImage(denoiser, \"output\", &view))");
    denoiser->denoiser->denoise(denoiser->frame, denoiser->output);
  });
}

RTDError rtdResetDenoiser(RTDDenoiser denoiser) {
  return guarded(deviceOf(denoiser), [&] {
    requireDenoiser(denoiser);
    denoiser->denoiser->reset();
  });
}

int rtdGetPassCount(RTDDenoiser denoiser) {
  int n = 0;
  guarded(deviceOf(denoiser), [&] {
    requireDenoiser(denoiser);
    n = int(denoiser->denoiser->stats().passes.size());
  });
  return n;
}

const char* rtdGetPassName(RTDDenoiser denoiser, int index) {
  const char* out = nullptr;
  guarded(deviceOf(denoiser), [&] { out = passAt(denoiser, index).name.c_str(); });
  return out;
}

double rtdGetPassMilliseconds(RTDDenoiser denoiser, int index) {
  double out = -1;
  guarded(deviceOf(denoiser), [&] { out = passAt(denoiser, index).milliseconds; });
  return out;
}

double rtdGetDenoiseMilliseconds(RTDDenoiser denoiser) {
  double out = 0;
  guarded(deviceOf(denoiser), [&] {
    requireDenoiser(denoiser);
    out = denoiser->denoiser->stats().totalMilliseconds;
  });
  return out;
}

uint64_t rtdGetSanitizedValueCount(RTDDenoiser denoiser) {
  uint64_t out = 0;
  guarded(deviceOf(denoiser), [&] {
    requireDenoiser(denoiser);
    out = denoiser->denoiser->stats().sanitizedValues;
  });
  return out;
}

int rtdGetMemoryCount(RTDDenoiser denoiser) {
  int n = 0;
  guarded(deviceOf(denoiser), [&] {
    requireDenoiser(denoiser);
    n = int(denoiser->denoiser->stats().memory.size());
  });
  return n;
}

const char* rtdGetMemoryCategory(RTDDenoiser denoiser, int index) {
  const char* out = nullptr;
  guarded(deviceOf(denoiser), [&] { out = memoryAt(denoiser, index).category.c_str(); });
  return out;
}

uint64_t rtdGetMemoryBytes(RTDDenoiser denoiser, int index) {
  uint64_t out = 0;
  guarded(deviceOf(denoiser), [&] { out = memoryAt(denoiser, index).bytes; });
  return out;
}

}  // extern "C"
