// Procedural texture patterns of the JSON scene description's material field "pattern"
// (docs/renderer.md): the textures of the procedural scene generator (src/render/procedural.cpp).
#pragma once
#include <cstdint>
#include <optional>
#include <string>

#include "render/scene.h"

namespace rtd::render {

/// Pattern kinds: "stripes", "dots", "bricks", "noise" (fractal value noise).
enum class Pattern { Stripes, Dots, Bricks, Noise };
std::optional<Pattern> patternFromName(const std::string& name);
const char* patternNames();  ///< "stripes, dots, bricks, noise" (for error messages)

/// A 256x256 texture blending colour `a` (background) and `b` (pattern) in `cells` repeats per
/// texture side; `seed` varies the noise pattern. Linear RGB; `mean` is filled.
Texture makePatternTexture(Pattern kind, V3 a, V3 b, int cells, uint32_t seed);

}  // namespace rtd::render
