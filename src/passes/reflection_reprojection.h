// Shared pass: where specular pixels take their history from (Voorhuis 2018, Sec. 4): the
// surface class of each pixel, and a reprojection in which pure-specular and glossy pixels
// follow the reflected geometry (diamond search, src/passes/diamond_search.h) instead of the
// primary hit, or are not reprojected at all (the paper's NoSpecReproj). GLSL twin:
// src/backend/vulkan/shaders/reflection_reproject.comp.
#pragma once
#include <cstdint>

#include "core/frame_data.h"
#include "passes/diamond_search.h"
#include "passes/reprojection.h"

namespace rtd {

/// How Voorhuis' pipeline treats a pixel, by the roughness of its primary hit (the note's
/// Sec. 2.1 table): the class decides the motion vector, the temporal blend factor,
/// neighbourhood clipping and the features the a-trous filter stops on.
enum class SurfaceClass : uint8_t {
  Diffuse = 0,           ///< roughness >= diffuse threshold (0.9), or the sky: primary MV, alpha 0.2, no clipping
  Glossy = 1,            ///< reflection threshold (0.4) <= roughness < 0.9: primary MV, clipped
  GlossyReflection = 2,  ///< roughness < 0.4, not a mirror: glossy MV search (Eq. 5), clipped
  Mirror = 3,            ///< pure specular: MV search on the reflected position (Eq. 1), clipped
};
inline bool isSpecular(SurfaceClass c) { return c != SurfaceClass::Diffuse; }

struct SurfaceClassThresholds {
  float pureSpecular = 0.02f;  ///< below: a mirror (the renderer's delta limit, kDeltaRoughness)
  float reflection = 0.4f;     ///< below: reflection motion vectors (Voorhuis Sec. 4.2.1, Beckmann 0.4)
  float diffuse = 0.9f;        ///< at or above: diffuse (Sec. 4.2.3 "not perfectly diffuse" < 0.9)
};

/// Which pixels of a radiance stream are specular. `specularLobe`: the stream holds only the
/// specular lobe (Specular, Blender's glossy passes), so every hit pixel reflects in it; a
/// smooth pixel is a mirror there whatever its metalness. Otherwise (the whole colour, or
/// direct / indirect) a smooth pixel is a mirror only where Metalness >= 0.5 (a smooth
/// dielectric is mostly diffuse), when the frame has Metalness. Without Roughness the classes
/// are Glossy for hit pixels of a specular lobe and Diffuse otherwise. Sky pixels (zero
/// normal) are Diffuse.
void classifySurfaces(const FrameData& f, const SurfaceClassThresholds& t, bool specularLobe, PixelVector<uint8_t>& out);

/// One key per pixel that tells surfaces apart: its class and, where the frame has ObjectId,
/// its object id (key = id * 4 + class, wrapping; ids are integer-valued). The clipping
/// neighbourhood of a pixel is the pixels of its key (ClipBoxOptions, clipBox's `surface`).
/// The key of one pixel: object id * 4 + class (ids are integer-valued floats, validated on
/// import, of any sign: through int64). Also the base of TAA's keys (passes/taa_keys.h).
inline uint32_t surfaceKey(float objectId, uint8_t cls) { return uint32_t(int64_t(objectId)) * 4u + cls; }
void surfaceKeys(const FrameData& f, const PixelVector<uint8_t>& cls, PixelVector<uint32_t>& out);

/// The buffers the reflection motion vectors read, per class: mirrors the reflected position;
/// glossy pixels the primary position, the mirror direction and the secondary distance.
bool hasMirrorMotionBuffers(const FrameData& f);
bool hasGlossyMotionBuffers(const FrameData& f);

/// What specular pixels reproject with (Voorhuis Sec. 7.1's configurations).
enum class SpecularMotion : uint8_t {
  Primary,     ///< the primary hit's motion, like every other pixel (Base)
  None,        ///< no history and no TAA for specular pixels (NoSpecReproj)
  Reflection,  ///< mirrors and glossy pixels below the reflection threshold follow the
               ///< reflected geometry; Glossy pixels keep the primary motion (Ours)
};

struct ReflectionMotionOptions {
  DiamondSearchOptions search;
  bool mirrors = true;  ///< search Mirror pixels (needs hasMirrorMotionBuffers)
  bool glossy = true;   ///< search GlossyReflection pixels (needs hasGlossyMotionBuffers)
  /// Mirror history taps must be mirror pixels whose reflected normals agree this well
  /// (cosine; the shared pass's normalTolerance). Glossy taps only need to be glossy pixels:
  /// Sec. 4.2.3 disables the consistency checks for glossy reflections.
  float normalTolerance = 0.9f;
};

/// Counts of one frame, for the statistics and the tests.
struct ReflectionMotionStats {
  uint64_t mirrorPixels = 0, glossyPixels = 0;  ///< pixels searched
  uint64_t matched = 0;                         ///< ... that found history
  uint64_t taps = 0;                            ///< distance evaluations of all searches
};

/// What a tap of the reflection search compares, for every searched pixel of one frame: at a
/// Mirror pixel Eq. 1's world position (the reflected position; for a mirror that shows the
/// sky, the point kMissDepth along its mirror direction), at a GlossyReflection pixel its
/// representative ray (Sec. 4.2.1, the direction of unit length). A search evaluates ~20-40
/// taps and neighbouring searches share most of them, so each pixel's feature is computed once
/// per frame instead of at every tap, and kept in one 32-byte record: a tap reads half a cache
/// line instead of the sky test's and the feature's six to seven planes.
class ReflectionSearchFeatures {
 public:
  union Record {
    float point[3];         ///< Mirror pixels
    RepresentativeRay ray;  ///< GlossyReflection pixels
    float bytes32[8];       ///< the record's size: two per cache line
  };
  /// The records of f's Mirror pixels (where f has hasMirrorMotionBuffers) and GlossyReflection
  /// pixels (hasGlossyMotionBuffers), classes from `cls`; other pixels' records are not set.
  void build(const FrameData& f, const PixelVector<uint8_t>& cls);
  const Record& operator[](size_t i) const { return records_[i]; }
  /// The records as floats (eight per pixel), for the memory report and the tests' checks.
  void forEachPlane(const PlaneVisitor& visit) const {
    if (!records_.empty()) visit("reflection search features", records_.front().bytes32, records_.size() * 8);
  }

 private:
  PixelVector<Record> records_;
};
static_assert(sizeof(ReflectionSearchFeatures::Record) == 32);

/// The reflection motion vector of current pixel (x, y): the search result of Algorithm 1 for
/// its class (Mirror: Eq. 1 on ReflectedPosition; GlossyReflection: Eq. 5 on the
/// representative rays) over the previous frame's features `prev` (built from the previous
/// frame and `prevCls`), with `primary` giving the second start (coords(p) - primary MV).
/// `bruteForceRadius` > 0 runs the brute-force reference over that window instead;
/// `glossyOnRay` measures glossy pixels by glossyRayDistance (the half-line) instead of Eq. 5.
SearchResult searchReflection(const FrameData& cur, const ReflectionSearchFeatures& prev, const PixelVector<uint8_t>& cls,
                              const PixelVector<uint8_t>& prevCls, const Reprojection& primary, int x, int y,
                              const DiamondSearchOptions& search, int bruteForceRadius = 0, bool glossyOnRay = false);

/// out = primary, then every specular pixel (class != Diffuse in `cls`) is redone per `mode`:
/// Primary leaves it; None makes it None with a previous position far off-screen (so TAA keeps
/// the current colour); Reflection gives Mirror and GlossyReflection pixels (where enabled in
/// `opt`) a bilinear record at the searched position, with history taps of the same class in
/// `prevCls` (None when there is none). With `previous` null, out = primary. `features`: where
/// the previous frame's search features are built (kept by a caller that runs every frame, so
/// that they are not allocated each time; null: a temporary).
void specularReprojection(const FrameData& cur, const FrameData* previous, const PixelVector<uint8_t>& cls,
                          const PixelVector<uint8_t>& prevCls, const Reprojection& primary, SpecularMotion mode,
                          const ReflectionMotionOptions& opt, Reprojection& out, ReflectionMotionStats* stats = nullptr,
                          ReflectionSearchFeatures* features = nullptr);

}  // namespace rtd
