// glTF 2.0 loading with tinygltf: meshes (triangles), node transforms, metallic-roughness
// materials with base-colour, metallic-roughness, emissive and normal textures, and cameras.
#include <tiny_gltf.h>

#include <fstream>
#include <map>
#include <sstream>

#include "render/scene.h"
#include "rtd/error.h"

namespace rtd::render {

namespace fs = std::filesystem;

namespace {

float srgbToLinear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

struct Loader {
  const tinygltf::Model& model;
  SceneData& scene;
  std::string file;
  std::map<std::pair<int, bool>, int> textureCache;  // (glTF texture, sRGB) -> our texture
  std::map<int, int> materialCache;
  int defaultMaterial = -1;

  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw Error("glTF '" + file + "': " + field + ": " + what);
  }

  int texture(int gltfTexture, bool srgb, const std::string& field) {
    if (gltfTexture < 0) return -1;
    auto key = std::make_pair(gltfTexture, srgb);
    if (auto it = textureCache.find(key); it != textureCache.end()) return it->second;
    if (gltfTexture >= int(model.textures.size())) fail(field, "texture index out of range");
    const int source = model.textures[gltfTexture].source;
    if (source < 0 || source >= int(model.images.size())) fail(field, "texture has no image");
    const tinygltf::Image& img = model.images[source];
    if (img.image.empty() || img.width <= 0 || img.height <= 0) fail(field, "image '" + img.uri + "' could not be decoded");
    if (img.bits != 8 && img.bits != 16) fail(field, "image '" + img.uri + "': unsupported bit depth");
    Texture t;
    t.width = img.width;
    t.height = img.height;
    t.texels.resize(size_t(t.width) * t.height);
    const int comp = img.component;
    const float scale = img.bits == 8 ? 1.0f / 255.0f : 1.0f / 65535.0f;
    V3 sum{0};
    for (size_t i = 0; i < t.texels.size(); ++i) {
      float c[3];
      for (int k = 0; k < 3; ++k) {
        const int ch = std::min(k, comp - 1);
        const size_t idx = i * comp + ch;
        const float v = img.bits == 8 ? img.image[idx] * scale
                                      : float(reinterpret_cast<const uint16_t*>(img.image.data())[idx]) * scale;
        c[k] = srgb ? srgbToLinear(v) : v;
      }
      t.texels[i] = {c[0], c[1], c[2]};
      sum += t.texels[i];
    }
    t.mean = sum / float(t.texels.size());
    scene.textures.push_back(std::move(t));
    return textureCache[key] = int(scene.textures.size()) - 1;
  }

  int material(int index) {
    if (index < 0) {
      if (defaultMaterial < 0) {
        scene.materials.push_back(Material{});
        defaultMaterial = int(scene.materials.size()) - 1;
      }
      return defaultMaterial;
    }
    if (auto it = materialCache.find(index); it != materialCache.end()) return it->second;
    if (index >= int(model.materials.size())) fail("materials", "index " + std::to_string(index) + " out of range");
    const tinygltf::Material& g = model.materials[index];
    const std::string field = "materials[" + std::to_string(index) + "]";
    Material m;
    m.name = g.name;
    const auto& pbr = g.pbrMetallicRoughness;
    m.baseColor = {float(pbr.baseColorFactor[0]), float(pbr.baseColorFactor[1]), float(pbr.baseColorFactor[2])};
    m.metallic = float(pbr.metallicFactor);
    m.roughness = float(pbr.roughnessFactor);
    m.emissive = {float(g.emissiveFactor[0]), float(g.emissiveFactor[1]), float(g.emissiveFactor[2])};
    // KHR_materials_emissive_strength scales the emissive factor.
    if (auto it = g.extensions.find("KHR_materials_emissive_strength"); it != g.extensions.end())
      if (it->second.Has("emissiveStrength")) m.emissive *= float(it->second.Get("emissiveStrength").GetNumberAsDouble());
    m.baseColorTexture = texture(pbr.baseColorTexture.index, true, field + ".baseColorTexture");
    m.metallicRoughnessTexture = texture(pbr.metallicRoughnessTexture.index, false, field + ".metallicRoughnessTexture");
    m.emissiveTexture = texture(g.emissiveTexture.index, true, field + ".emissiveTexture");
    m.normalTexture = texture(g.normalTexture.index, false, field + ".normalTexture");
    m.normalScale = float(g.normalTexture.scale);
    scene.materials.push_back(m);
    return materialCache[index] = int(scene.materials.size()) - 1;
  }

  /// Reads accessor `index` as floats, `comps` per element (normalized integers allowed).
  std::vector<float> floats(int index, int comps, const std::string& field) const {
    if (index < 0 || index >= int(model.accessors.size())) fail(field, "accessor index out of range");
    const tinygltf::Accessor& a = model.accessors[index];
    const int n = tinygltf::GetNumComponentsInType(a.type);
    if (n != comps) fail(field, "expected " + std::to_string(comps) + " components, got " + std::to_string(n));
    if (a.bufferView < 0) return std::vector<float>(a.count * comps, 0.0f);  // sparse-only: zeros
    const tinygltf::BufferView& bv = model.bufferViews[a.bufferView];
    const auto& buf = model.buffers[bv.buffer].data;
    const int csize = tinygltf::GetComponentSizeInBytes(a.componentType);
    const size_t stride = bv.byteStride ? bv.byteStride : size_t(csize) * comps;
    const size_t start = bv.byteOffset + a.byteOffset;
    if (a.count > 0 && start + stride * (a.count - 1) + size_t(csize) * comps > buf.size()) fail(field, "accessor runs past its buffer");
    std::vector<float> out(a.count * comps);
    for (size_t i = 0; i < a.count; ++i)
      for (int c = 0; c < comps; ++c) {
        const unsigned char* p = buf.data() + start + i * stride + size_t(c) * csize;
        float v;
        switch (a.componentType) {
          case TINYGLTF_COMPONENT_TYPE_FLOAT: std::memcpy(&v, p, 4); break;
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: v = *p / 255.0f; break;
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t s; std::memcpy(&s, p, 2); v = s / 65535.0f; break; }
          default: fail(field, "unsupported component type " + std::to_string(a.componentType));
        }
        out[i * comps + c] = v;
      }
    return out;
  }

  std::vector<uint32_t> indices(int index, size_t vertexCount, const std::string& field) const {
    if (index < 0) {
      std::vector<uint32_t> seq(vertexCount);
      for (size_t i = 0; i < vertexCount; ++i) seq[i] = uint32_t(i);
      return seq;
    }
    if (index >= int(model.accessors.size())) fail(field, "accessor index out of range");
    const tinygltf::Accessor& a = model.accessors[index];
    const tinygltf::BufferView& bv = model.bufferViews.at(a.bufferView);
    const auto& buf = model.buffers.at(bv.buffer).data;
    const int csize = tinygltf::GetComponentSizeInBytes(a.componentType);
    const size_t stride = bv.byteStride ? bv.byteStride : size_t(csize);
    const size_t start = bv.byteOffset + a.byteOffset;
    if (a.count > 0 && start + stride * (a.count - 1) + csize > buf.size()) fail(field, "accessor runs past its buffer");
    std::vector<uint32_t> out(a.count);
    for (size_t i = 0; i < a.count; ++i) {
      const unsigned char* p = buf.data() + start + i * stride;
      uint32_t v = 0;
      if (csize == 1) v = *p;
      else if (csize == 2) { uint16_t s; std::memcpy(&s, p, 2); v = s; }
      else std::memcpy(&v, p, 4);
      if (v >= vertexCount) fail(field, "index " + std::to_string(v) + " exceeds the vertex count");
      out[i] = v;
    }
    return out;
  }

  static M4 nodeMatrix(const tinygltf::Node& n) {
    if (n.matrix.size() == 16) {
      M4 m;  // glTF stores column-major
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) m(r, c) = float(n.matrix[c * 4 + r]);
      return m;
    }
    TransformKey k;
    if (n.translation.size() == 3) k.translation = {float(n.translation[0]), float(n.translation[1]), float(n.translation[2])};
    if (n.rotation.size() == 4) k.rotation = {float(n.rotation[0]), float(n.rotation[1]), float(n.rotation[2]), float(n.rotation[3])};
    if (n.scale.size() == 3) k.scale = {float(n.scale[0]), float(n.scale[1]), float(n.scale[2])};
    return k.matrix();
  }

  void node(int index, const M4& parent, bool& takeCamera, int depth) {
    if (index < 0 || index >= int(model.nodes.size())) fail("nodes", "index " + std::to_string(index) + " out of range");
    if (depth > 256) fail("nodes", "hierarchy too deep (a cycle?)");
    const tinygltf::Node& n = model.nodes[index];
    const M4 world = parent * nodeMatrix(n);
    if (n.mesh >= 0) addMesh(n.mesh, world, n.name.empty() ? "node" + std::to_string(index) : n.name);
    if (n.camera >= 0 && takeCamera) {
      const tinygltf::Camera& c = model.cameras.at(n.camera);
      CameraKey k;
      if (c.type == "perspective") k.fovY = float(c.perspective.yfov) * 180.0f / kPi;
      k.position = world.point(V3(0));
      k.target = k.position + normalize(world.vector(V3(0, 0, -1)));
      k.up = normalize(world.vector(V3(0, 1, 0)));
      scene.cameraKeys = {k};
      takeCamera = false;
    }
    for (int child : n.children) node(child, world, takeCamera, depth + 1);
  }

  void addMesh(int meshIndex, const M4& world, const std::string& name) {
    const tinygltf::Mesh& gm = model.meshes.at(meshIndex);
    for (size_t pi = 0; pi < gm.primitives.size(); ++pi) {
      const tinygltf::Primitive& prim = gm.primitives[pi];
      const std::string field = "meshes[" + std::to_string(meshIndex) + "].primitives[" + std::to_string(pi) + "]";
      if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1) continue;  // points and lines are not rendered
      auto pos = prim.attributes.find("POSITION");
      if (pos == prim.attributes.end()) fail(field, "has no POSITION attribute");
      Mesh m;
      const auto p = floats(pos->second, 3, field + ".POSITION");
      for (size_t i = 0; i + 2 < p.size(); i += 3) m.positions.push_back({p[i], p[i + 1], p[i + 2]});
      if (auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end()) {
        const auto nn = floats(it->second, 3, field + ".NORMAL");
        for (size_t i = 0; i + 2 < nn.size(); i += 3) m.normals.push_back({nn[i], nn[i + 1], nn[i + 2]});
        if (m.normals.size() != m.positions.size()) fail(field + ".NORMAL", "count differs from POSITION");
      }
      if (auto it = prim.attributes.find("TEXCOORD_0"); it != prim.attributes.end()) {
        m.uvs = floats(it->second, 2, field + ".TEXCOORD_0");
        if (m.uvs.size() != 2 * m.positions.size()) fail(field + ".TEXCOORD_0", "count differs from POSITION");
      }
      m.indices = indices(prim.indices, m.positions.size(), field + ".indices");
      if (m.indices.size() % 3) fail(field + ".indices", "count is not a multiple of 3");
      if (m.indices.empty()) continue;
      scene.meshes.push_back(std::move(m));
      Object o;
      o.name = name;
      o.mesh = int(scene.meshes.size()) - 1;
      o.material = material(prim.material);
      o.base = world;
      scene.objects.push_back(o);
    }
  }
};

std::string fileBytesHash(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return hashHex(ss.str());
}

}  // namespace

void loadGltf(const fs::path& file, SceneData& scene, const M4& root, bool takeCamera) {
  if (!fs::exists(file)) throw Error("glTF '" + file.string() + "': file not found");
  tinygltf::TinyGLTF gltf;
  tinygltf::Model model;
  std::string err, warn;
  std::string ext = file.extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  const bool ok = ext == ".glb" ? gltf.LoadBinaryFromFile(&model, &err, &warn, file.string())
                                : gltf.LoadASCIIFromFile(&model, &err, &warn, file.string());
  if (!ok) throw Error("glTF '" + file.string() + "': " + (err.empty() ? std::string("cannot be parsed") : err));
  Loader l{model, scene, file.string(), {}, {}, -1};
  const int sceneIndex = model.defaultScene >= 0 ? model.defaultScene : 0;
  if (!model.scenes.empty()) {
    for (int n : model.scenes.at(sceneIndex).nodes) l.node(n, root, takeCamera, 0);
  } else {
    for (size_t n = 0; n < model.nodes.size(); ++n) l.node(int(n), root, takeCamera, 0);
  }
  if (scene.objects.empty()) throw Error("glTF '" + file.string() + "': no triangle meshes in the scene");
  // Images referenced by URI change the picture too; hashing the main file covers .glb only,
  // so also hash each external buffer/image file.
  scene.hashText += "gltf:" + fileBytesHash(file);
  for (const auto& img : model.images)
    if (!img.uri.empty() && img.uri.rfind("data:", 0) != 0) scene.hashText += ":" + fileBytesHash(file.parent_path() / img.uri);
  for (const auto& b : model.buffers)
    if (!b.uri.empty() && b.uri.rfind("data:", 0) != 0) scene.hashText += ":" + fileBytesHash(file.parent_path() / b.uri);
}

}  // namespace rtd::render
