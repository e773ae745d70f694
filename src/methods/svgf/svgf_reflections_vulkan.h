// SVGF's Voorhuis mode on the Vulkan backend: the twin of svgf::Reflections
// (svgf_reflections.h), pass for pass, recorded through a vk::Recorder. The shared passes are
// src/backend/vulkan/shaders/{surface_class,reflection_reproject,clip_box}.comp; SVGF's own
// glue is shaders/voorhuis_*.comp here.
#pragma once
#if defined(RTD_HAS_VULKAN)
#include "backend/vulkan/passes.h"
#include "methods/svgf/svgf_reflections.h"

namespace rtd::svgf {

/// The features the a-trous filter stops on: depth (1 plane), normal (3) and the depth
/// gradient (2) (AtrousGuide on the CPU).
struct GpuGuide {
  const vk::Planes* depth = nullptr;
  const vk::Planes* normal = nullptr;
  const vk::Planes* gradient = nullptr;
};

class GpuReflections {
 public:
  /// A new frame size: drops every plane; prepare allocates them at the frame's size when the
  /// parts first run (none are kept while no part is on).
  void resize(vk::Context& ctx, int w, int h);
  void reset() { hasPreviousClasses_ = false; }

  /// Classes, the specular reprojection, the blend floor, Eq. 6 falloff and the reflected
  /// guide; once per frame after the primary reprojection.
  void prepare(vk::Recorder& rec, const vk::GpuFrame& frame, const vk::GpuFrame* previous, const SvgfSettings& s,
               const ReflectionParts& parts, bool lobes, const vk::Planes& primary);

  struct StreamInputs {
    const vk::Planes* reprojection;
    GpuGuide guide;
    const vk::Planes* alpha = nullptr;
    const vk::Planes* falloff = nullptr;
    const vk::Planes* surfaceKey = nullptr;  ///< Reflections::StreamInputs::surfaceKey
    const vk::Planes* albedo = nullptr;  ///< demodulation colour, or null
  };
  StreamInputs stream(vk::Recorder& rec, const vk::GpuFrame& frame, const StreamPlan& plan, const vk::Planes& primary,
                      const GpuGuide& primaryGuide, int index);
  /// The clipping box (6 planes) of a stream's demodulated sample, or null.
  const vk::Planes* clipBox(vk::Recorder& rec, const vk::Planes& demod, const StreamPlan& plan, const SvgfSettings& s);
  /// The reprojection TAA reads (Reflections::taaMotion).
  const vk::Planes& taaMotion(vk::Recorder& rec, const vk::GpuFrame& frame, const vk::Planes& primary, bool glossy,
                              SvgfTaaMirrorHistory mirrors = SvgfTaaMirrorHistory::reflectionMotion);

  const ReflectionParts& parts() const { return parts_; }
  /// This frame's classes (1 plane, SurfaceClass as float), for tests.
  const vk::Planes& classes() const { return cls_[cur_]; }
  const vk::Planes& specularReprojection() const { return specular_; }

 private:
  void allocate(vk::Context& ctx, int w, int h);
  ReflectionParts parts_;
  bool lobes_ = false, hasPreviousClasses_ = false;
  vk::Planes cls_[2];
  int cur_ = 0;
  vk::Planes specular_, taa_;
  vk::Planes guideDepth_, guideNormal_, gradientIn_, gradient_;
  vk::Planes alpha_, falloff_, mirrorKey_;
  vk::Planes albedo_[2];
  vk::Planes clip_, clipRows_, clipBlur_;
  vk::Binding objectId_;  ///< this frame's ObjectId (prepare), for the clipping surfaces
  bool hasObjectId_ = false;
};

}  // namespace rtd::svgf
#endif
