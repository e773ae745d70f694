// rtdenoise — two-view (stereo, VR) denoising: both eyes' frames in, both eyes' outputs out.
//
//   auto device = rtd::Device::create();
//   auto stereo = device->createStereoDenoiser(rtd::SvgfSettings::forVariant(rtd::SvgfVariant::gersthofer));
//   for each frame:
//     rtd::StereoFrameInputs in;
//     in.eye[0] = left;   // rtd::FrameInputs with its own camera (Camera::valid) and buffers
//     in.eye[1] = right;  // optional in each: Buffer::HiddenArea, Buffer::SampleMask
//     stereo->denoise(in, leftOutput, rightOutput);
//
// Every method runs on two views: each eye keeps its own history, as a single-view denoiser
// per eye would. Methods with a two-view pipeline also share light between the eyes: `svgf`
// with components = composite and eyeReprojection (the gersthofer variant) projects each
// eye's world positions into the other eye and blends the other eye's accumulated indirect
// diffuse light in (Gersthofer 2020, Sec. 3.4.2); that needs Position, Normal and Depth and
// both eyes' cameras. Single-view methods (Denoiser) are unchanged by this header.
#pragma once
#include <array>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "rtd/denoiser.h"

namespace rtd {

/// The two views of one stereo frame: eye[0] is the left eye, eye[1] the right one. Both must
/// have the same size. cameraCut on either eye resets both.
struct StereoFrameInputs {
  std::array<FrameInputs, 2> eye;
};

/// A denoiser for a stereo pair: the history of both eyes' image streams. Not thread-safe.
class StereoDenoiser {
 public:
  virtual ~StereoDenoiser() = default;

  virtual std::string_view method() const = 0;
  virtual Backend backend() const = 0;
  /// Buffers this method needs in each eye's frame (as Denoiser::requiredBuffers()).
  virtual std::vector<Buffer> requiredBuffers() const = 0;

  /// Settings by name and by type, checked as on a Denoiser (both eyes share them).
  virtual std::vector<SettingInfo> settings() const = 0;
  virtual void set(std::string_view name, std::string_view value) = 0;
  template <class S> void setSettings(const S& s) { assignSettings(S::kMethod, &s); }
  template <class S> S getSettings() const {
    return *static_cast<const S*>(const_cast<StereoDenoiser*>(this)->settingsStorage(S::kMethod));
  }

  /// Denoises both eyes of one frame into `left` and `right` (each the size of its eye's
  /// colour, Float3 or Float4; the Denoiser::denoise contract per eye). Throws rtd::Error on a
  /// missing buffer or a size mismatch before touching history.
  virtual void denoise(const StereoFrameInputs& frame, const ImageView& left, const ImageView& right) = 0;

  /// Forgets both eyes' history.
  virtual void reset() = 0;

  /// The last call: pass times summed over both eyes (a pass both eyes ran once appears
  /// once, with the sum; passes of the pair itself such as "eyeReprojection" as they are),
  /// totals and memory of both eyes together.
  virtual const FrameStats& stats() const = 0;
  /// The last call for one eye alone (0 left, 1 right).
  virtual const FrameStats& eyeStats(int eye) const = 0;

 protected:
  /// The current settings struct of `method`; throws rtd::Error for another method.
  virtual void* settingsStorage(std::string_view method) = 0;
  /// Validates `settings` (a settings struct of `method`) and makes them both eyes' settings.
  virtual void assignSettings(std::string_view method, const void* settings) = 0;
};

/// rtd::applySettings (rtd/denoiser.h) for both eyes: presets first, then the others in order.
void applySettings(StereoDenoiser& denoiser, const std::vector<SettingAssignment>& assignments);

template <class S>
  requires requires { S::kMethod; }
std::unique_ptr<StereoDenoiser> Device::createStereoDenoiser(const S& settings) {
  auto d = createStereoDenoiser(S::kMethod);
  d->setSettings(settings);
  return d;
}

}  // namespace rtd
