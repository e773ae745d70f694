// The renderer's scene model: meshes, materials, textures, animated objects, lights and the
// camera path, filled by the JSON description parser, the glTF loader or a built-in scene.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "render/math.h"
#include "rtd/render/render.h"

namespace rtd::render {

/// Linear RGB texture, bilinear lookup with repeat wrapping (glTF's default sampler).
struct Texture {
  int width = 0, height = 0;
  std::vector<V3> texels;  ///< linear RGB, rows from the top (glTF's v = 0 is the top)
  V3 mean{0};
  V3 sample(float u, float v) const;
};

struct Material {
  std::string name;
  V3 baseColor{0.8f};
  float metallic = 0.0f;
  float roughness = 0.5f;  ///< perceptual roughness; GGX alpha = roughness^2
  /// Dielectric specular strength: F0 = 0.08 * specular (0.5 -> F0 = 0.04, as glTF); 0 makes a
  /// pure Lambertian surface (the white-furnace tests need one).
  float specular = 0.5f;
  V3 emissive{0};  ///< emitted radiance (both sides)
  int baseColorTexture = -1, metallicRoughnessTexture = -1, emissiveTexture = -1, normalTexture = -1;
  float normalScale = 1.0f;
  bool isEmissive() const { return maxComponent(emissive) > 0; }
};

struct Mesh {
  std::vector<V3> positions;
  std::vector<V3> normals;     ///< per vertex, may be empty (flat shading)
  std::vector<float> uvs;      ///< 2 per vertex, may be empty
  std::vector<uint32_t> indices;
  /// An analytic sphere centred at the local origin: shading normals are exact (p / |p|).
  bool analyticSphere = false;
};

/// Translation, rotation (unit quaternion x, y, z, w) and scale at one frame.
struct TransformKey {
  float frame = 0;
  V3 translation{0};
  std::array<float, 4> rotation{0, 0, 0, 1};
  V3 scale{1};
  /// Multiplier of the object's emitted radiance (JSON "emission"; a light switch), linear
  /// between keys like the transform.
  float emission = 1.0f;
  M4 matrix() const { return render::translation(translation) * render::rotation(rotation) * render::scaling(scale); }
};

struct Object {
  std::string name;
  int mesh = 0;
  int material = 0;
  M4 base;                          ///< static part (glTF node world matrix)
  std::vector<TransformKey> keys;   ///< animation applied after `base`; empty: static
  /// World matrix at (fractional) frame index `t` (0-based): keys interpolated, clamped at the ends.
  M4 worldAt(float t) const;
  /// Emission multiplier at frame `t` (1 without keys).
  float emissionAt(float t) const;
  bool animated() const { return keys.size() > 1; }
};

struct CameraKey {
  float frame = 0;
  V3 position{0, 1, 5};
  V3 target{0, 1, 0};
  V3 up{0, 1, 0};
  float fovY = 45.0f;  ///< vertical field of view, degrees
};

/// A view at one frame: eye position, orthonormal axes and the OpenGL-style projection.
struct View {
  V3 eye, right, up, forward;  ///< forward = -Z of camera space
  float tanHalfFovY = 0.4f, aspect = 1.0f;
  float nearPlane = 0.01f, farPlane = 1000.0f;
  M4 worldToCamera() const;
  M4 projection() const;
};

struct Sun {
  V3 direction{0, 1, 0};  ///< unit vector towards the sun
  V3 irradiance{0};       ///< irradiance on a surface facing the sun (W/m^2 per channel)
  float angleDegrees = 0; ///< angular radius of the sun disc; 0 = directional (delta) light
  bool enabled() const { return maxComponent(irradiance) > 0; }
};

/// Sky radiance: `zenith` at the top, `horizon` at the horizon (linear in the elevation's sine),
/// `ground` below the horizon. A constant sky has all three equal.
struct Sky {
  V3 zenith{0}, horizon{0}, ground{0};
  V3 radiance(V3 dir) const {
    if (dir.y < 0) return ground;
    return lerp(horizon, zenith, std::min(1.0f, dir.y));
  }
  bool enabled() const { return maxComponent(zenith) > 0 || maxComponent(horizon) > 0 || maxComponent(ground) > 0; }
};

class SceneData final : public Scene {
 public:
  std::string name_ = "scene";
  std::string source;  ///< file or built-in name, for messages
  std::vector<Texture> textures;
  std::vector<Material> materials;
  std::vector<Mesh> meshes;
  std::vector<Object> objects;
  std::vector<CameraKey> cameraKeys;
  bool catmullRom = false;
  Sun sun;
  Sky sky;
  int frames = 1;
  RenderSettings settings;
  std::string hashText;  ///< canonical description text for contentHash()

  int frameCount() const override { return frames; }
  RenderSettings suggestedSettings() const override { return settings; }
  std::string contentHash() const override;
  std::string name() const override { return name_; }

  /// Camera keyframe interpolated at frame `t` (0-based).
  CameraKey cameraAt(float t) const;
  /// The view of frame `t` for an image of `aspect` = width / height, shifted for an eye.
  View viewAt(float t, float aspect, Eye eye, float eyeDistance) const;
  bool anyAnimated() const;
};

/// Parses a JSON scene description (docs/renderer.md) into `scene`.
void parseSceneJson(const std::string& text, const std::filesystem::path& baseDir, const std::string& source,
                    SceneData& scene);
/// Appends the meshes, materials, textures, objects (and the first camera, if `takeCamera`) of a
/// glTF 2.0 file (.gltf or .glb) to `scene`, under an extra transform `root`.
void loadGltf(const std::filesystem::path& file, SceneData& scene, const M4& root, bool takeCamera);
/// JSON text of a built-in scene, or nullopt.
std::optional<std::string> builtinSceneJson(const std::string& name);

/// Procedural meshes in local space: unit quad in XZ (normal +Y), unit cube, sphere of radius
/// 0.5, cylinder of radius 0.5 and height 1 (axis Y), all centred at the origin.
Mesh makeQuad();
Mesh makeBox();
Mesh makeSphere(int segments = 48, int rings = 24);
Mesh makeCylinder(int segments = 32);

/// 64-bit FNV-1a of a string, as hex (reference-cache keys).
std::string hashHex(const std::string& text);

}  // namespace rtd::render
