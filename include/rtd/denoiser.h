// rtdenoise — the device and the denoiser: the whole public API of the library besides I/O.
//
//   auto device = rtd::Device::create({.backend = rtd::Backend::Cpu});
//   auto denoiser = device->createDenoiser(rtd::SvgfSettings{});   // or createDenoiser("svgf")
//   for each frame: fill rtd::FrameInputs, then denoiser->denoise(frame, output);
//   on a camera cut: denoiser->reset();
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "rtd/error.h"
#include "rtd/frame.h"
#include "rtd/settings.h"

namespace rtd {

class StereoDenoiser;  // rtd/stereo.h
namespace detail { struct DenoiserAccess; }

enum class Backend { Cpu, Vulkan };
std::string_view backendName(Backend b);

/// Time one pass took in the last frame (CPU wall time, or GPU time from timestamp queries).
struct PassTiming {
  std::string name;
  double milliseconds = 0;
  /// CPU backend: the CPU time the process spent during the pass, all threads together (on a
  /// machine shared with other work this grows far less than the wall time; with one thread it
  /// is the pass's own cost). 0 where not measured (Vulkan).
  double cpuMilliseconds = 0;
};

/// What import did to the values of one buffer of a frame (both backends alike; the ranges are
/// in docs/input-validation.md). Nothing non-finite and nothing outside these ranges reaches
/// a method, so every weight and every history stays finite.
struct SanitizeCounts {
  uint64_t nonFinite = 0;     ///< NaN and +-Inf values, replaced by 0
  /// Finite values clamped into the buffer's range: negative radiance to 0, radiance above
  /// kMaxRadiance (a firefly no filter should spread) to it, guides beyond their bounds.
  uint64_t outOfRange = 0;
  /// Pixels of a unit-vector buffer (normal, reflectedNormal, mirrorDirection) whose length was
  /// not 1, renormalized (a (0, 0, 0) vector means "no surface" and is kept).
  uint64_t renormalized = 0;
  uint64_t total() const { return nonFinite + outOfRange + renormalized; }
};

/// Memory a denoiser holds for one purpose (the categories of Gersthofer's Table 5.4).
struct MemoryUse {
  /// "frames": the imported inputs (this frame's and the previous frame's buffers, the
  /// G-buffer's counterpart); "history": what carries over to the next frame; "intermediate":
  /// per-frame working planes; "planes": history and working planes together, where a method
  /// does not tell them apart (float planes on the CPU, where small integer arrays are not
  /// counted; every other device-local buffer on Vulkan); "staging" (Vulkan): host-visible
  /// upload, read-back and counter buffers. The categories of one report add up to all the
  /// denoiser holds (on the CPU: all its float planes).
  std::string category;
  uint64_t bytes = 0;
};

/// What the last denoise() call did.
struct FrameStats {
  std::vector<PassTiming> passes;
  double totalMilliseconds = 0;
  /// Every value import replaced, all buffers together: the sum of sanitized[b].total().
  uint64_t sanitizedValues = 0;
  /// The same per buffer, indexed by int(Buffer).
  std::array<SanitizeCounts, kBufferCount> sanitized{};
  uint64_t pixels = 0;
  /// Memory held after the call, by category (MemoryUse): "frames" and "planes" for every
  /// method on both backends, plus "staging" on Vulkan; svgf with components = composite
  /// reports Gersthofer's "history" and "intermediate" in place of (CPU) or beside (Vulkan)
  /// "planes".
  std::vector<MemoryUse> memory;
  /// Parts of the method that were asked for but did not run on this frame, and why (e.g.
  /// "glossyBandwidth off: the frame has no 'reflectedFootprint' buffer").
  std::vector<std::string> notes;
};

/// A denoiser owns the history of one image stream. Not thread-safe; use one per stream.
class Denoiser {
 public:
  virtual ~Denoiser() = default;

  virtual std::string_view method() const = 0;
  virtual Backend backend() const = 0;
  /// Buffers this method needs in every frame (always includes Buffer::Color).
  virtual std::vector<Buffer> requiredBuffers() const = 0;

  /// Current settings, by name. set() throws rtd::Error for an unknown name or a bad value.
  virtual std::vector<SettingInfo> settings() const = 0;
  virtual void set(std::string_view name, std::string_view value) = 0;

  /// Typed settings: `denoiser->setSettings(rtd::SvgfSettings{...})`. Checked like settings
  /// given by name (every field finite, within the range and choices its visit() documents):
  /// throws rtd::Error naming the first bad field, or if the settings type belongs to another
  /// method, and then leaves settings and history as they were.
  template <class S> void setSettings(const S& s) { assignSettings(S::kMethod, &s); }
  template <class S> S getSettings() const {
    return *static_cast<const S*>(const_cast<Denoiser*>(this)->settingsStorage(S::kMethod));
  }

  /// Denoise one frame. `output` must have the input's size, Float3, Float4, Half3 or Half4
  /// (alpha is set to 1); it receives linear RGB radiance, remodulated, not tone-mapped. The
  /// frame's conventions (FrameConventions) are converted to the native ones after import. A
  /// frame whose size differs from the previous one resizes the history (and resets it). Throws
  /// rtd::Error on a missing required buffer or a size mismatch, before touching history.
  virtual void denoise(const FrameInputs& frame, const ImageView& output) = 0;

  /// Forget all history (camera cut, scene change).
  virtual void reset() = 0;

  /// Timings and counts of the last denoise() call.
  virtual const FrameStats& stats() const = 0;

 protected:
  virtual void* settingsStorage(std::string_view method) = 0;
  /// Validates `settings` (a settings struct of `method`) and makes them current.
  virtual void assignSettings(std::string_view method, const void* settings) = 0;
  virtual void settingsChanged() {}
  friend struct detail::DenoiserAccess;  // two-view denoisers made of two Denoisers reach these
};

struct DeviceDesc {
  Backend backend = Backend::Cpu;
  int threads = 0;           ///< CPU worker threads; 0 = all cores
  std::string vulkanDevice;  ///< Vulkan: device index or part of its name; empty = best
  bool vulkanValidation = false;  ///< Vulkan: enable validation layers if installed
};

/// A compute device (CPU thread pool or Vulkan device). Create denoisers from it.
class Device {
 public:
  /// Throws rtd::Error when the backend is unavailable (e.g. no Vulkan device).
  static std::unique_ptr<Device> create(const DeviceDesc& desc = {});
  virtual ~Device() = default;
  virtual Backend backend() const = 0;
  virtual std::string name() const = 0;

  /// Create a denoiser by method name ("accumulate", "svgf", "bmfr", ...) with default settings.
  virtual std::unique_ptr<Denoiser> createDenoiser(std::string_view method) = 0;
  template <class S>
    requires requires { S::kMethod; }
  std::unique_ptr<Denoiser> createDenoiser(const S& settings) {
    auto d = createDenoiser(S::kMethod);
    d->setSettings(settings);
    return d;
  }

  /// A two-view denoiser (rtd/stereo.h) of any method, default settings: the method's stereo
  /// pipeline where it has one (svgf: Gersthofer's eye reprojection), else one history per eye.
  virtual std::unique_ptr<StereoDenoiser> createStereoDenoiser(std::string_view method) = 0;
  template <class S>
    requires requires { S::kMethod; }
  std::unique_ptr<StereoDenoiser> createStereoDenoiser(const S& settings);
};

/// A device `rtdenoise devices` lists.
struct DeviceInfo {
  Backend backend = Backend::Cpu;
  int index = 0;            ///< Vulkan: the index DeviceDesc::vulkanDevice accepts
  std::string name;         ///< Vulkan: the name DeviceDesc::vulkanDevice matches (substring)
  std::string description;  ///< type, API version, driver
};

/// Every device this build can run on: the CPU, then each Vulkan device. Where Vulkan is not
/// available, `vulkanError` (if not null) receives the reason.
std::vector<DeviceInfo> listDevices(std::string* vulkanError = nullptr);

/// Every registered method with its settings' defaults.
std::vector<MethodInfo> listMethods();

/// One setting by name and its value as text ("sigmaLuminance", "4").
using SettingAssignment = std::pair<std::string, std::string>;

/// Sets several settings by name as one request: presets (SettingInfo::preset, e.g. SVGF's
/// "variant") first, then the others in the order given, so that a preset never overrides a
/// setting given with it whatever the order. Throws rtd::Error, before changing anything, for
/// an unknown name or a name given twice; a bad value throws as Denoiser::set() does.
void applySettings(Denoiser& denoiser, const std::vector<SettingAssignment>& assignments);

}  // namespace rtd
