// rtdenoise — what one frame hands a denoiser: named buffers and the camera.
#pragma once
#include <array>
#include <optional>
#include <string_view>

#include "rtd/image.h"

namespace rtd {

/// The buffers a frame may carry. Each has a canonical name, used as the channel-layer name in
/// the native sequence format (e.g. `color.R`, `normal.X`, `depth.Z`); see docs/sequence-format.md.
/// Conventions (all methods, all backends):
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
  ReflectedPosition,  ///< first non-mirror hit's world position for mirror pixels, XYZ
  ReflectedNormal,    ///< first non-mirror hit's world normal for mirror pixels, XYZ
  ReflectedAlbedo,    ///< first non-mirror hit's albedo for mirror pixels, RGB
  SecondaryDistance,  ///< distance from the primary to the secondary hit, Z
  MirrorDirection,    ///< perfect mirror direction at the primary hit, XYZ
  Seed,               ///< per-pixel random seed (A-SVGF re-shading), id
  SampleMask,         ///< 1 where the pixel was traced this frame, 0 where it is empty, V
  /// Radiance emitted towards the camera by the primary hit (emitters, and the sky where no
  /// surface was hit), RGB, part of Color (and of Direct and Diffuse). Noise-free at pixel
  /// centres, so denoisers subtract it before filtering and add it back to their output:
  /// bright emitters then cannot bleed into their neighbours.
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

/// One frame's inputs: a view per buffer (empty where the frame has none) and its camera.
struct FrameInputs {
  std::array<ImageView, kBufferCount> buffers{};
  Camera camera;
  /// Set when the application knows history is invalid (a camera cut); same as Denoiser::reset().
  bool cameraCut = false;

  ImageView& operator[](Buffer b) { return buffers[int(b)]; }
  const ImageView& operator[](Buffer b) const { return buffers[int(b)]; }
  bool has(Buffer b) const { return !buffers[int(b)].empty(); }
};

}  // namespace rtd
