// The two-view denoiser of any method (rtd/stereo.h) as two single-view denoisers, one per
// eye, with one set of settings; methods with a stereo pipeline of their own derive from it
// and take over denoise() when their settings ask for it.
#pragma once
#include <memory>
#include <string>

#include "rtd/stereo.h"

namespace rtd {

namespace detail {
/// Reaches a Denoiser's typed settings storage (Denoiser befriends it).
struct DenoiserAccess {
  static void* settingsStorage(Denoiser& d, std::string_view method) { return d.settingsStorage(method); }
  static void assignSettings(Denoiser& d, std::string_view method, const void* s) { d.assignSettings(method, s); }
};
}  // namespace detail

/// Both eyes' stats as one: each pass's time summed over the eyes (in the left eye's order,
/// then passes only the right eye ran), totals, sanitized values, pixels and memory summed.
FrameStats combineEyeStats(const FrameStats& left, const FrameStats& right);

class StereoPair : public StereoDenoiser {
 public:
  StereoPair(std::unique_ptr<Denoiser> left, std::unique_ptr<Denoiser> right);

  std::string_view method() const override { return eyes_[0]->method(); }
  Backend backend() const override { return eyes_[0]->backend(); }
  std::vector<Buffer> requiredBuffers() const override { return eyes_[0]->requiredBuffers(); }
  std::vector<SettingInfo> settings() const override { return eyes_[0]->settings(); }
  void set(std::string_view name, std::string_view value) override;
  /// Both eyes in turn; validates both frames (sizes, required buffers) before either eye runs.
  void denoise(const StereoFrameInputs& frame, const ImageView& left, const ImageView& right) override;
  void reset() override;
  const FrameStats& stats() const override { return stats_; }
  const FrameStats& eyeStats(int eye) const override { return eyeStats_[eye & 1]; }

 protected:
  void* settingsStorage(std::string_view method) override {
    return detail::DenoiserAccess::settingsStorage(*eyes_[0], method);
  }
  /// The left eye validates (and refuses before anything changes), then the right takes the same.
  void assignSettings(std::string_view method, const void* settings) override {
    detail::DenoiserAccess::assignSettings(*eyes_[0], method, settings);
    detail::DenoiserAccess::assignSettings(*eyes_[1], method, settings);
  }
  /// Throws rtd::Error unless both eyes' frames and outputs have one size and the required buffers.
  void validate(const StereoFrameInputs& frame, const ImageView& left, const ImageView& right) const;

  std::unique_ptr<Denoiser> eyes_[2];
  FrameStats stats_, eyeStats_[2];
};

}  // namespace rtd
