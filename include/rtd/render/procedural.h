// rtdenoise renderer — the procedural scene generator: a random scene (objects, materials incl.
// glossy, metal and mirror, textures, area lights and/or sun and sky, an animated camera path)
// drawn from a seed, written as a JSON scene description (docs/renderer.md). The same seed gives
// the same text on every platform (own integer RNG, no std:: distributions). Used by
// `rtdenoise dataset` for training data and by `Scene::load("procedural:<seed>")`.
#pragma once
#include <cstdint>
#include <string>

namespace rtd::render {

struct ProceduralOptions {
  int frames = 8;      ///< length of the camera path (and of object animations), frames
  int width = 256;     ///< resolution written into the description
  int height = 256;
};

/// The JSON scene description of procedural scene `seed`, named "procedural_<seed>".
std::string proceduralSceneJson(uint32_t seed, const ProceduralOptions& options = {});

/// Prefix of procedural scene names for Scene::load: "procedural:<seed>" (default options) or
/// "procedural:<seed>:<frames>".
constexpr const char* kProceduralPrefix = "procedural:";

}  // namespace rtd::render
