// rtdenoise — what one frame hands a denoiser: named buffers and the camera.
#pragma once
#include <array>
#include <optional>
#include <string_view>
#include <vector>

#include "rtd/image.h"
#include "rtd/settings.h"
#include "rtd/settings_visit.h"

namespace rtd {

/// The buffers a frame may carry. Each has a canonical name, used as the channel-layer name in
/// the native sequence format (e.g. `color.R`, `normal.X`, `depth.Z`); see docs/sequence-format.md.
/// Native conventions (all methods, all backends; FrameConventions converts an engine's own):
///  - radiance is linear, scene-referred, not tone-mapped;
///  - normals are world-space, unit length; positions are world-space;
///  - depth is linear view depth: distance along the camera axis (= -z in camera space);
///  - motion is in pixels: the previous-frame position of the centre of pixel (x, y) is
///    (x + 0.5 + motion.X, y + 0.5 + motion.Y), rows counted from the top (y down).
/// Import sanitizes every buffer the same way on every backend (FrameStats::sanitized counts
/// it; docs/input-validation.md has the table): NaN and Inf become 0; finite values are clamped
/// into the buffer's range (radiance [0, kMaxRadiance], depth [0, kMaxGuideMagnitude], ...);
/// unit vectors (normals, directions) that are not of unit length are renormalized.
/// Radiance above this is clamped to it on import (and counted): the largest half float, which
/// any real 1-spp sample stays below, while a pixel of 1e30 would otherwise live in an
/// exponential history for hundreds of frames and overflow the squares SVGF and BMFR compute.
constexpr float kMaxRadiance = 65504.0f;
/// Bound of the magnitude of depths, positions, distances and depth gradients on import: far
/// beyond any scene (Blender writes a sky depth of 1e10), small enough that the squares and
/// products of two such values (distances, least-squares features) stay finite in float.
constexpr float kMaxGuideMagnitude = 1e18f;

enum class Buffer : int {
  Color,              ///< noisy radiance, RGB (required by every method)
  Albedo,             ///< albedo of the primary hit, RGB, used for demodulation
  Normal,             ///< world-space shading normal, XYZ
  Depth,              ///< linear view depth, Z
  Position,           ///< world-space position of the primary hit, XYZ
  Motion,             ///< screen-space motion to the previous frame in pixels, XY
  ObjectId,           ///< object id (integer-valued), id
  MaterialId,         ///< material id (integer-valued), id
  Roughness,          ///< perceptual roughness of the primary hit, V
  Metalness,          ///< metalness of the primary hit, V
  DepthGradient,      ///< screen-space derivative of depth, XY
  Direct,             ///< direct part of Color, RGB (optional split component)
  Indirect,           ///< indirect part of Color, RGB (optional split component)
  Diffuse,            ///< diffuse part of Color, RGB (optional split component)
  Specular,           ///< specular part of Color, RGB (optional split component)
  ReflectedPosition,  ///< first non-mirror hit of the perfect mirror ray (mirror and glossy pixels), XYZ
  ReflectedNormal,    ///< first non-mirror hit's world normal (mirror and glossy pixels), XYZ
  ReflectedAlbedo,    ///< first non-mirror hit's albedo (mirror and glossy pixels), RGB
  SecondaryDistance,  ///< distance from the primary to the secondary hit, Z
  MirrorDirection,    ///< perfect mirror direction at the primary hit, XYZ
  Seed,               ///< per-pixel random seed (A-SVGF re-shading), id
  SampleMask,         ///< 1 where the pixel was traced this frame, 0 where it is empty, V
  /// Radiance emitted towards the camera by the primary hit (emitters, and the sky where no
  /// surface was hit), RGB, part of Color (and of Direct and Diffuse). Noise-free at pixel
  /// centres, so denoisers subtract it before filtering and add it back to their output:
  /// bright emitters then cannot bleed into their neighbours. The renderer also counts here
  /// (and in Direct and Diffuse) what is as noise-free: an emitter or the sky seen through
  /// perfect mirrors (metallic 1, roughness below the delta limit), times the mirrors' Fresnel;
  /// Blender's Emit pass holds the directly visible emission only.
  Emission,
  /// A-SVGF gradient samples (Schied et al. 2018; docs/sequence-format.md "Gradient samples"):
  /// 1 at the one pixel of a 3x3 stratum (strata at multiples of 3 from the top-left corner)
  /// that holds the stratum's gradient sample, 0 elsewhere, V.
  GradientSample,
  /// Rec. 709 luminance of the gradient sample's radiance in the previous frame, at the pixel
  /// holding it (0 elsewhere), V.
  GradientPrevious,
  /// Rec. 709 luminance of the same sample re-shaded in this frame: the previous frame's
  /// surface point moved with its object, traced with the previous frame's random numbers, V.
  GradientCurrent,
  /// For glossy and mirror pixels: (|dP/dx| + |dP/dy|) / 2 of the ray differentials (Igehy
  /// 1999) at the first non-mirror hit of the perfect mirror ray, world units per pixel, V
  /// (Voorhuis Eq. 6); 0 elsewhere.
  ReflectedFootprint,
  /// Colour that demodulates the Diffuse stream where it is not Albedo (Blender's DiffCol), RGB.
  DiffuseAlbedo,
  /// Colour that demodulates the Specular stream (Blender's GlossCol), RGB.
  SpecularAlbedo,
  /// Indirect diffuse part of Color, RGB: light reaching the primary hit through a diffuse
  /// first bounce (Gersthofer Sec. 3.3: the component shared between the eyes). Color minus it
  /// is "direct + indirect specular"; the two are composited before filtering.
  IndirectDiffuse,
  /// 1 where the head-mounted display's lens hides the pixel (the hidden-area mesh, Gersthofer
  /// Sec. 3.1), 0 where it is visible, V. Hidden pixels are neither traced nor filtered and come
  /// out 0.
  HiddenArea,
  Count
};
constexpr int kBufferCount = int(Buffer::Count);

/// Canonical name of a buffer ("color", "normal", ...).
std::string_view bufferName(Buffer b);
/// Channel suffixes of a buffer in order ("R","G","B" / "X","Y","Z" / "Z" / "id" / "V").
std::string_view bufferChannels(Buffer b);  // e.g. "RGB", "XYZ", "XY", "Z", "V", "I" (id)
/// Number of channels of a buffer.
int bufferChannelCount(Buffer b);
/// The buffer with this canonical name, if any.
std::optional<Buffer> bufferFromName(std::string_view name);

/// Camera of one frame. Matrices are row-major and act on column vectors (p' = M p).
/// `worldToCamera` maps world space to a right-handed camera space looking down -Z;
/// `projection` maps camera space to OpenGL clip space (x right, y up, NDC in [-1, 1]).
struct Camera {
  std::array<float, 16> worldToCamera{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  std::array<float, 16> projection{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  bool valid = false;  ///< false when the source gave no camera
};

/// How an engine's buffers differ from the native conventions (see Buffer), in the spirit of
/// NRD's common settings: the denoiser converts them to the native ones once per frame, right
/// after import, on either backend. The defaults are the native conventions (nothing converted,
/// nothing spent). Every field but `depthProjection` can also be set by name (setConvention()).
struct FrameConventions {
  enum class MotionUnits { Pixels, Uv, Ndc };
  enum class NormalSpace { World, View };
  enum class DepthKind { Linear, Hardware };
  enum class DepthRange { ZeroToOne, MinusOneToOne };

  /// Buffer::Motion's unit: Pixels; Uv, where 1 is the image's width (x) or height (y); or Ndc,
  /// where 2 is the width or height.
  MotionUnits motionUnits = MotionUnits::Pixels;
  /// Motion's y axis points up the image (OpenGL NDC, many engines' UV) rather than down the rows.
  bool motionYUp = false;
  /// Motion points from the previous position to the current one (current - previous) rather
  /// than to the previous one.
  bool motionToCurrent = false;
  /// The motion vectors were computed with the jittered projections of both frames, so they
  /// hold the jitter difference (jitter - previousJitter), which is removed.
  bool motionIncludesJitter = false;
  /// Sub-pixel jitter of this frame's camera, in pixels, x right and y down the rows: the sample
  /// of pixel (x, y) lies at (x + 0.5 + jitterX, y + 0.5 + jitterY) of the unjittered image.
  /// Reprojection reads history at the unjittered position, so history stays aligned with the
  /// pixel centres while the samples move: motion that includes the jitter is corrected, and
  /// motion derived from positions and the cameras (no Buffer::Motion) is shifted by -jitter.
  /// `camera.projection` is the unjittered one.
  float jitterX = 0, jitterY = 0;
  /// The previous frame's jitter, for motionIncludesJitter.
  float previousJitterX = 0, previousJitterY = 0;
  /// Buffer::Normal is world space, or view space: the camera space of camera.worldToCamera
  /// (the frame's camera must then be valid); view-space normals are rotated to world space.
  NormalSpace normalSpace = NormalSpace::World;
  /// Buffer::Depth is linear view depth, or the hardware depth buffer's value d in [0, 1]
  /// written with `depthProjection`, converted to linear depth |z| by inverting that matrix's
  /// third and fourth rows. Reversed-Z and infinite far planes need nothing more than the
  /// matching matrix; depth at an infinite far plane (and any depth beyond 1e30) becomes 1e30.
  DepthKind depth = DepthKind::Linear;
  /// NDC depth range of `depthProjection`: ZeroToOne (Vulkan, Direct3D; d = ndc.z) or
  /// MinusOneToOne (OpenGL; d = (ndc.z + 1) / 2).
  DepthRange depthRange = DepthRange::ZeroToOne;
  /// The projection that wrote the depth buffer (row-major, clip = P * camera-space point), in
  /// the engine's own API convention; only its third and fourth rows are used.
  std::array<float, 16> depthProjection{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

  /// True when every field has its native default (no conversion).
  bool native() const;

  template <class V> void visit(V& v) {
    v("motionUnits", motionUnits, "unit of motion vectors: pixels, uv (1 = image size) or ndc (2 = image size)",
      {"pixels", "uv", "ndc"});
    v("motionYUp", motionYUp, "motion's y axis points up the image (native: down the rows)");
    v("motionToCurrent", motionToCurrent, "motion is current - previous position (native: previous - current)");
    v("motionIncludesJitter", motionIncludesJitter, "motion was computed with jittered projections (jitter removed)");
    v("jitterX", jitterX, "sub-pixel camera jitter of this frame, pixels, x right", Range{-1, 1});
    v("jitterY", jitterY, "sub-pixel camera jitter of this frame, pixels, y down", Range{-1, 1});
    v("previousJitterX", previousJitterX, "the previous frame's jitterX", Range{-1, 1});
    v("previousJitterY", previousJitterY, "the previous frame's jitterY", Range{-1, 1});
    v("normalSpace", normalSpace, "space of normals: world, or view (camera.worldToCamera's camera space)",
      {"world", "view"});
    v("depth", depth, "depth is linear view depth, or the hardware depth buffer (depthProjection)",
      {"linear", "hardware"});
    v("depthRange", depthRange, "NDC z range of depthProjection: zeroToOne (Vulkan, D3D) or minusOneToOne (OpenGL)",
      {"zeroToOne", "minusOneToOne"});
  }
};

/// The conventions' fields as `rtdenoise methods` lists settings (name, type, value, doc).
std::vector<SettingInfo> conventionSettings(const FrameConventions& c = {});
/// Sets a field of `c` by name from text; throws rtd::Error for an unknown name or a bad value
/// (leaving `c` unchanged).
void setConvention(FrameConventions& c, std::string_view name, std::string_view value);

/// One frame's inputs: a view per buffer (empty where the frame has none) and its camera.
struct FrameInputs {
  std::array<ImageView, kBufferCount> buffers{};
  Camera camera;
  /// How the buffers differ from the native conventions (default: they do not).
  FrameConventions conventions;
  /// Set when the application knows history is invalid (a camera cut); same as Denoiser::reset().
  bool cameraCut = false;

  ImageView& operator[](Buffer b) { return buffers[int(b)]; }
  const ImageView& operator[](Buffer b) const { return buffers[int(b)]; }
  bool has(Buffer b) const { return !buffers[int(b)].empty(); }
};

}  // namespace rtd
