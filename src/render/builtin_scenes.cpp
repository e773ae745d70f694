// Built-in procedural scenes, written in the same JSON scene description a user would write
// (docs/renderer.md), so each doubles as an example: `rtdenoise render --print-scene NAME`.
#include <map>
#include <string>

#include "render/scene.h"

namespace rtd::render {

namespace {

// A Cornell box (2 x 2 x 2 units) with a ceiling light, two boxes and a slow lateral camera pan.
constexpr const char* kCornell = R"({
  "name": "cornell",
  "frames": 60,
  "resolution": [320, 180],
  "materials": {
    "white": {"baseColor": [0.73, 0.73, 0.73], "specular": 0},
    "red":   {"baseColor": [0.65, 0.05, 0.05], "specular": 0},
    "green": {"baseColor": [0.12, 0.45, 0.15], "specular": 0},
    "light": {"baseColor": [0.78, 0.78, 0.78], "emissive": [17, 12, 4]}
  },
  "objects": [
    {"name": "floor",   "shape": "quad", "material": "white", "scale": [2, 1, 2]},
    {"name": "ceiling", "shape": "quad", "material": "white", "translation": [0, 2, 0], "rotation": [180, 0, 0], "scale": [2, 1, 2]},
    {"name": "back",    "shape": "quad", "material": "white", "translation": [0, 1, -1], "rotation": [90, 0, 0], "scale": [2, 1, 2]},
    {"name": "left",    "shape": "quad", "material": "red",   "translation": [-1, 1, 0], "rotation": [0, 0, -90], "scale": [2, 1, 2]},
    {"name": "right",   "shape": "quad", "material": "green", "translation": [1, 1, 0], "rotation": [0, 0, 90], "scale": [2, 1, 2]},
    {"name": "light",   "shape": "quad", "material": "light", "translation": [0, 1.995, 0], "rotation": [180, 0, 0], "scale": [0.5, 1, 0.4]},
    {"name": "tall",    "shape": "box",  "material": "white", "translation": [-0.33, 0.6, -0.3], "rotation": [0, 18, 0], "scale": [0.6, 1.2, 0.6]},
    {"name": "short",   "shape": "box",  "material": "white", "translation": [0.35, 0.3, 0.35], "rotation": [0, -17, 0], "scale": [0.6, 0.6, 0.6]}
  ],
  "camera": {"fov": 40, "keyframes": [
    {"frame": 0,  "position": [-0.35, 1, 3.9], "target": [0, 1, 0]},
    {"frame": 59, "position": [0.35, 1, 3.9],  "target": [0, 1, 0]}
  ]}
})";

// A colonnade of pillars under a low sun; the camera moves sideways, so pillars uncover and
// cover the background every frame (many disocclusions).
constexpr const char* kPillars = R"({
  "name": "pillars",
  "frames": 60,
  "resolution": [320, 180],
  "materials": {
    "floor":  {"baseColor": [0.75, 0.72, 0.65], "roughness": 0.8, "checker": {"color": [0.25, 0.24, 0.22], "cells": 40}},
    "stone":  {"baseColor": [0.7, 0.68, 0.62], "roughness": 0.7},
    "wall":   {"baseColor": [0.55, 0.35, 0.25], "roughness": 0.9, "checker": {"color": [0.45, 0.28, 0.2], "cells": 16}}
  },
  "objects": [
    {"name": "floor", "shape": "quad", "material": "floor", "scale": [40, 1, 40]},
    {"name": "wall",  "shape": "box",  "material": "wall",  "translation": [0, 2, -4], "scale": [24, 4, 0.4]},
    {"name": "p0", "shape": "cylinder", "material": "stone", "translation": [-6, 1.5, -1], "scale": [0.5, 3, 0.5]},
    {"name": "p1", "shape": "cylinder", "material": "stone", "translation": [-4, 1.5, -1], "scale": [0.5, 3, 0.5]},
    {"name": "p2", "shape": "cylinder", "material": "stone", "translation": [-2, 1.5, -1], "scale": [0.5, 3, 0.5]},
    {"name": "p3", "shape": "cylinder", "material": "stone", "translation": [0, 1.5, -1], "scale": [0.5, 3, 0.5]},
    {"name": "p4", "shape": "cylinder", "material": "stone", "translation": [2, 1.5, -1], "scale": [0.5, 3, 0.5]},
    {"name": "p5", "shape": "cylinder", "material": "stone", "translation": [4, 1.5, -1], "scale": [0.5, 3, 0.5]},
    {"name": "p6", "shape": "cylinder", "material": "stone", "translation": [6, 1.5, -1], "scale": [0.5, 3, 0.5]},
    {"name": "q0", "shape": "cylinder", "material": "stone", "translation": [-5, 1.5, 1.5], "scale": [0.5, 3, 0.5]},
    {"name": "q1", "shape": "cylinder", "material": "stone", "translation": [-3, 1.5, 1.5], "scale": [0.5, 3, 0.5]},
    {"name": "q2", "shape": "cylinder", "material": "stone", "translation": [-1, 1.5, 1.5], "scale": [0.5, 3, 0.5]},
    {"name": "q3", "shape": "cylinder", "material": "stone", "translation": [1, 1.5, 1.5], "scale": [0.5, 3, 0.5]},
    {"name": "q4", "shape": "cylinder", "material": "stone", "translation": [3, 1.5, 1.5], "scale": [0.5, 3, 0.5]},
    {"name": "q5", "shape": "cylinder", "material": "stone", "translation": [5, 1.5, 1.5], "scale": [0.5, 3, 0.5]},
    {"name": "beam0", "shape": "box", "material": "stone", "translation": [0, 3.15, -1], "scale": [13, 0.3, 0.7]},
    {"name": "beam1", "shape": "box", "material": "stone", "translation": [0, 3.15, 1.5], "scale": [11, 0.3, 0.7]}
  ],
  "sun": {"direction": [0.6, 0.55, 0.35], "irradiance": [3.2, 2.9, 2.4], "angle": 0.5},
  "sky": {"zenith": [0.25, 0.4, 0.8], "horizon": [0.7, 0.75, 0.85], "ground": [0.2, 0.2, 0.2]},
  "camera": {"fov": 50, "keyframes": [
    {"frame": 0,  "position": [-3, 1.6, 6], "target": [-3, 1.4, 0]},
    {"frame": 59, "position": [3, 1.6, 6],  "target": [3, 1.4, 0]}
  ]}
})";

// Mirrors and glossy metals of increasing roughness over a glossy checkered floor.
constexpr const char* kGlossy = R"({
  "name": "glossy",
  "frames": 60,
  "resolution": [320, 180],
  "materials": {
    "floor":  {"baseColor": [0.8, 0.8, 0.8], "roughness": 0.25, "checker": {"color": [0.1, 0.1, 0.12], "cells": 24}},
    "mirror": {"baseColor": [0.95, 0.95, 0.95], "mirror": true},
    "wall":   {"baseColor": [0.6, 0.55, 0.5], "roughness": 0.9, "checker": {"color": [0.3, 0.45, 0.6], "cells": 10}},
    "gold05": {"baseColor": [1.0, 0.78, 0.34], "metallic": 1, "roughness": 0.05},
    "gold15": {"baseColor": [1.0, 0.78, 0.34], "metallic": 1, "roughness": 0.15},
    "gold30": {"baseColor": [1.0, 0.78, 0.34], "metallic": 1, "roughness": 0.3},
    "gold55": {"baseColor": [1.0, 0.78, 0.34], "metallic": 1, "roughness": 0.55},
    "plastic": {"baseColor": [0.1, 0.3, 0.8], "roughness": 0.3, "specular": 0.5}
  },
  "objects": [
    {"name": "floor",   "shape": "quad",   "material": "floor",  "scale": [16, 1, 16]},
    {"name": "backwall","shape": "quad",   "material": "wall",   "translation": [0, 2, -3], "rotation": [90, 0, 0], "scale": [16, 1, 4]},
    {"name": "mirrorwall", "shape": "box", "material": "mirror", "translation": [-3.2, 1.2, -0.5], "rotation": [0, -45, 0], "scale": [0.05, 2.4, 2.5]},
    {"name": "mirrorball", "shape": "sphere", "material": "mirror", "translation": [0, 0.8, -0.8], "scale": 1.6},
    {"name": "s05", "shape": "sphere", "material": "gold05", "translation": [-1.8, 0.35, 1.0], "scale": 0.7},
    {"name": "s15", "shape": "sphere", "material": "gold15", "translation": [-0.6, 0.35, 1.2], "scale": 0.7},
    {"name": "s30", "shape": "sphere", "material": "gold30", "translation": [0.6, 0.35, 1.2], "scale": 0.7},
    {"name": "s55", "shape": "sphere", "material": "gold55", "translation": [1.8, 0.35, 1.0], "scale": 0.7},
    {"name": "cube", "shape": "box", "material": "plastic", "translation": [2.2, 0.5, -1.2], "rotation": [0, 35, 0], "scale": 1.0}
  ],
  "sun": {"direction": [-0.4, 0.8, 0.45], "irradiance": [2.6, 2.5, 2.3], "angle": 0.5},
  "sky": {"zenith": [0.2, 0.35, 0.75], "horizon": [0.75, 0.8, 0.9], "ground": [0.25, 0.25, 0.25]},
  "camera": {"fov": 45, "interpolation": "catmull-rom", "keyframes": [
    {"frame": 0,  "position": [-2.0, 1.8, 5.5], "target": [0, 0.6, 0]},
    {"frame": 30, "position": [0.0, 1.5, 5.8],  "target": [0, 0.6, 0]},
    {"frame": 59, "position": [2.0, 1.8, 5.5],  "target": [0, 0.6, 0]}
  ]}
})";

// A room with a moving ball, a spinning box and a moving light: object motion, moving shadows
// and lighting changes (what temporal filters find hardest). The default scene of the demo.
constexpr const char* kDynamic = R"({
  "name": "dynamic",
  "frames": 48,
  "resolution": [320, 180],
  "materials": {
    "floor": {"baseColor": [0.8, 0.78, 0.74], "roughness": 0.6, "checker": {"color": [0.3, 0.3, 0.32], "cells": 12}},
    "wall":  {"baseColor": [0.75, 0.72, 0.68], "roughness": 0.9, "specular": 0.2},
    "red":   {"baseColor": [0.7, 0.12, 0.1], "roughness": 0.9, "specular": 0.2},
    "ball":  {"baseColor": [0.9, 0.9, 0.9], "metallic": 1, "roughness": 0.2},
    "box":   {"baseColor": [0.15, 0.45, 0.75], "roughness": 0.4},
    "lamp":  {"baseColor": [1, 1, 1], "emissive": [120, 104, 80]}
  },
  "objects": [
    {"name": "floor", "shape": "quad", "material": "floor", "scale": [8, 1, 8]},
    {"name": "back",  "shape": "quad", "material": "wall",  "translation": [0, 2, -2], "rotation": [90, 0, 0], "scale": [8, 1, 4]},
    {"name": "left",  "shape": "quad", "material": "red",   "translation": [-3, 2, 1], "rotation": [0, 0, -90], "scale": [4, 1, 6]},
    {"name": "pillar", "shape": "cylinder", "material": "wall", "translation": [1.6, 1, -1.2], "scale": [0.4, 2, 0.4]},
    {"name": "ball", "shape": "sphere", "material": "ball", "scale": 0.8, "animation": [
      {"frame": 0,  "translation": [-1.8, 0.4, 0.2]},
      {"frame": 24, "translation": [0.2, 0.4, 0.8]},
      {"frame": 47, "translation": [1.8, 0.4, 0.2]}
    ]},
    {"name": "box", "shape": "box", "material": "box", "translation": [-0.5, 0.35, -0.9], "scale": 0.7, "animation": [
      {"frame": 0,  "rotation": [0, 0, 0]},
      {"frame": 47, "rotation": [0, 120, 0]}
    ]},
    {"name": "lamp", "shape": "sphere", "material": "lamp", "scale": 0.2, "animation": [
      {"frame": 0,  "translation": [-1.5, 2.2, 0.8]},
      {"frame": 47, "translation": [1.5, 2.0, 1.2]}
    ]}
  ],
  "sky": {"zenith": [0.08, 0.1, 0.16], "horizon": [0.12, 0.12, 0.14], "ground": [0.05, 0.05, 0.05]},
  "camera": {"fov": 50, "keyframes": [
    {"frame": 0,  "position": [-0.8, 1.4, 4.5], "target": [0, 0.7, 0]},
    {"frame": 47, "position": [0.8, 1.5, 4.3],  "target": [0, 0.7, 0]}
  ]}
})";

// A light switch (A-SVGF's case, Schied et al. 2018): a still room lit by a ceiling lamp that
// switches off at frame 16 and on again at frame 32, and a small warm lamp that stays on; a ball
// rolls under the ceiling lamp, so its shadow moves. The camera is still, so every lag comes
// from the lighting (rtdenoise render --scene lightswitch; scripts/asvgf-experiments.sh).
constexpr const char* kLightswitch = R"({
  "name": "lightswitch",
  "frames": 48,
  "resolution": [320, 180],
  "materials": {
    "floor": {"baseColor": [0.8, 0.78, 0.74], "roughness": 0.7, "checker": {"color": [0.35, 0.35, 0.38], "cells": 10}},
    "wall":  {"baseColor": [0.75, 0.72, 0.68], "roughness": 0.9, "specular": 0.2},
    "blue":  {"baseColor": [0.2, 0.35, 0.7], "roughness": 0.9, "specular": 0.2},
    "ball":  {"baseColor": [0.85, 0.3, 0.2], "roughness": 0.4},
    "box":   {"baseColor": [0.3, 0.6, 0.35], "roughness": 0.6},
    "ceiling": {"baseColor": [1, 1, 1], "emissive": [30, 28, 24]},
    "warm":  {"baseColor": [1, 1, 1], "emissive": [60, 36, 14]}
  },
  "objects": [
    {"name": "floor", "shape": "quad", "material": "floor", "scale": [8, 1, 8]},
    {"name": "back",  "shape": "quad", "material": "wall",  "translation": [0, 2, -2], "rotation": [90, 0, 0], "scale": [8, 1, 4]},
    {"name": "left",  "shape": "quad", "material": "blue",  "translation": [-3, 2, 1], "rotation": [0, 0, -90], "scale": [4, 1, 6]},
    {"name": "box",   "shape": "box",  "material": "box",   "translation": [1.3, 0.4, -0.8], "rotation": [0, 25, 0], "scale": 0.8},
    {"name": "ceilingLamp", "shape": "quad", "material": "ceiling", "rotation": [180, 0, 0], "scale": [1.2, 1, 0.8],
     "animation": [{"frame": 0, "translation": [0, 2.8, 0.2], "emission": 1}, {"frame": 15, "emission": 1},
                   {"frame": 16, "emission": 0}, {"frame": 31, "emission": 0}, {"frame": 32, "emission": 1}]},
    {"name": "warmLamp", "shape": "sphere", "material": "warm", "translation": [-2.4, 0.5, -1.4], "scale": 0.16},
    {"name": "ball", "shape": "sphere", "material": "ball", "scale": 0.6, "animation": [
      {"frame": 0,  "translation": [-1.6, 0.3, 0.6]},
      {"frame": 47, "translation": [1.4, 0.3, 0.9]}
    ]}
  ],
  "sky": {"color": 0.02},
  "camera": {"fov": 50, "position": [0, 1.6, 4.6], "target": [0, 0.6, 0]}
})";

// Higginson Sec. 1.3.2's ghosting demo: a perfect mirror as the whole ground, a blue cube and a
// light-emitting plane whose reflection slides across the floor as the camera turns around the
// cube. Reflections have no motion vectors of their own, so history lags behind them.
constexpr const char* kGhosting = R"({
  "name": "ghosting",
  "frames": 48,
  "resolution": [320, 180],
  "materials": {
    "mirror": {"baseColor": [0.95, 0.95, 0.95], "mirror": true},
    "cube":   {"baseColor": [0.1, 0.2, 0.8], "roughness": 0.5},
    "panel":  {"baseColor": [1, 1, 1], "emissive": [6, 6, 6]}
  },
  "objects": [
    {"name": "floor", "shape": "quad", "material": "mirror", "scale": [20, 1, 20]},
    {"name": "cube",  "shape": "box",  "material": "cube", "translation": [0, 0.5, 0], "rotation": [0, 20, 0]},
    {"name": "panel", "shape": "quad", "material": "panel", "translation": [0, 1.5, -3], "rotation": [90, 0, 0], "scale": [3, 1, 1.6]}
  ],
  "sky": {"zenith": [0.05, 0.07, 0.12], "horizon": [0.12, 0.12, 0.14], "ground": [0.05, 0.05, 0.05]},
  "camera": {"fov": 50, "interpolation": "catmull-rom", "keyframes": [
    {"frame": 0,  "position": [-3.0, 2.2, 2.6], "target": [0, 0.4, 0]},
    {"frame": 16, "position": [-1.2, 2.4, 3.8], "target": [0, 0.4, 0]},
    {"frame": 32, "position": [1.2, 2.4, 3.8],  "target": [0, 0.4, 0]},
    {"frame": 47, "position": [3.0, 2.2, 2.6],  "target": [0, 0.4, 0]}
  ]}
})";


// Voorhuis 2018's test cases (docs/methods/reflections.md): a mirror floor under a camera that
// slides sideways (the virtual image of everything moves against the floor), and a corridor
// flythrough past a mirror orb / a glossy orb, the only specular object (Sec. 7.4, CORRIDOR).
constexpr const char* kMirrorFloor = R"({
  "name": "mirrorfloor",
  "frames": 48,
  "resolution": [320, 180],
  "materials": {
    "mirror": {"baseColor": [0.9, 0.9, 0.9], "mirror": true},
    "wall":   {"baseColor": [0.7, 0.62, 0.5], "roughness": 1, "specular": 0, "checker": {"color": [0.2, 0.3, 0.55], "cells": 14}},
    "red":    {"baseColor": [0.8, 0.15, 0.1], "roughness": 1, "specular": 0},
    "green":  {"baseColor": [0.15, 0.6, 0.2], "roughness": 1, "specular": 0, "checker": {"color": [0.9, 0.85, 0.3], "cells": 4}},
    "white":  {"baseColor": [0.75, 0.75, 0.75], "roughness": 1, "specular": 0}
  },
  "objects": [
    {"name": "floor", "shape": "quad", "material": "mirror", "scale": [30, 1, 30]},
    {"name": "back",  "shape": "quad", "material": "wall", "translation": [0, 2.5, -4], "rotation": [90, 0, 0], "scale": [30, 1, 5]},
    {"name": "box",   "shape": "box", "material": "red", "translation": [-1.4, 0.6, -1.6], "rotation": [0, 25, 0], "scale": 1.2},
    {"name": "ball",  "shape": "sphere", "material": "green", "translation": [0.6, 0.55, -0.8], "scale": 1.1},
    {"name": "post",  "shape": "cylinder", "material": "white", "translation": [2.2, 1.0, -2.4], "scale": [0.5, 2, 0.5]}
  ],
  "sun": {"direction": [-0.4, 0.75, 0.5], "irradiance": [2.6, 2.5, 2.3], "angle": 0.5},
  "sky": {"zenith": [0.2, 0.35, 0.75], "horizon": [0.75, 0.8, 0.9], "ground": [0.25, 0.25, 0.25]},
  "camera": {"fov": 50, "keyframes": [
    {"frame": 0,  "position": [-2.0, 1.3, 4.0], "target": [-2.0, 0.5, -1.0]},
    {"frame": 47, "position": [2.0, 1.3, 4.0],  "target": [2.0, 0.5, -1.0]}
  ]}
})";

// The corridor: checkered diffuse walls, floor and ceiling, ceiling lamps, an orb in the
// middle; the camera flies along it and passes the orb. `%ORB%` is the orb's material.
constexpr const char* kCorridor = R"({
  "name": "%NAME%",
  "frames": 60,
  "resolution": [320, 180],
  "materials": {
    "orb":     %ORB%,
    "floor":   {"baseColor": [0.7, 0.68, 0.62], "roughness": 1, "specular": 0, "checker": {"color": [0.25, 0.22, 0.2], "cells": 20}},
    "wallL":   {"baseColor": [0.75, 0.3, 0.2], "roughness": 1, "specular": 0, "checker": {"color": [0.85, 0.8, 0.6], "cells": 24}},
    "wallR":   {"baseColor": [0.2, 0.4, 0.75], "roughness": 1, "specular": 0, "checker": {"color": [0.8, 0.85, 0.9], "cells": 24}},
    "ceiling": {"baseColor": [0.8, 0.8, 0.8], "roughness": 1, "specular": 0},
    "end":     {"baseColor": [0.3, 0.65, 0.3], "roughness": 1, "specular": 0, "checker": {"color": [0.9, 0.9, 0.5], "cells": 6}},
    "lamp":    {"baseColor": [1, 1, 1], "emissive": [12, 11, 9]}
  },
  "objects": [
    {"name": "floor",   "shape": "quad", "material": "floor", "translation": [0, 0, -6], "scale": [4, 1, 20]},
    {"name": "ceiling", "shape": "quad", "material": "ceiling", "translation": [0, 3, -6], "rotation": [180, 0, 0], "scale": [4, 1, 20]},
    {"name": "left",    "shape": "quad", "material": "wallL", "translation": [-2, 1.5, -6], "rotation": [0, 0, -90], "scale": [3, 1, 20]},
    {"name": "right",   "shape": "quad", "material": "wallR", "translation": [2, 1.5, -6], "rotation": [0, 0, 90], "scale": [3, 1, 20]},
    {"name": "end",     "shape": "quad", "material": "end", "translation": [0, 1.5, -16], "rotation": [90, 0, 0], "scale": [4, 1, 3]},
    {"name": "lamp1",   "shape": "quad", "material": "lamp", "translation": [0, 2.99, -2], "rotation": [180, 0, 0], "scale": [1, 1, 0.6]},
    {"name": "lamp2",   "shape": "quad", "material": "lamp", "translation": [0, 2.99, -8], "rotation": [180, 0, 0], "scale": [1, 1, 0.6]},
    {"name": "lamp3",   "shape": "quad", "material": "lamp", "translation": [0, 2.99, -13], "rotation": [180, 0, 0], "scale": [1, 1, 0.6]},
    {"name": "orb",     "shape": "sphere", "material": "orb", "translation": [0.3, 1.1, -7], "scale": 1.4}
  ],
  "camera": {"fov": 55, "interpolation": "catmull-rom", "keyframes": [
    {"frame": 0,  "position": [-0.9, 1.5, 3.0],  "target": [0.2, 1.1, -7]},
    {"frame": 30, "position": [0.6, 1.6, -1.5],  "target": [0.3, 1.1, -7]},
    {"frame": 59, "position": [1.3, 1.4, -4.0],  "target": [-0.2, 1.0, -9]}
  ]}
})";

std::string corridor(const char* name, const char* orb) {
  std::string s = kCorridor;
  s.replace(s.find("%NAME%"), 6, name);
  s.replace(s.find("%ORB%"), 5, orb);
  return s;
}

const std::map<std::string, std::string>& table() {
  static const std::map<std::string, std::string> t = {
      {"cornell", kCornell},
      {"pillars", kPillars},
      {"glossy", kGlossy},
      {"dynamic", kDynamic},
      {"lightswitch", kLightswitch},
      {"ghosting", kGhosting},
      {"mirrorfloor", kMirrorFloor},
      {"corridor", corridor("corridor", R"({"baseColor": [0.95, 0.95, 0.95], "mirror": true})")},
      {"corridorglossy", corridor("corridorglossy", R"({"baseColor": [0.95, 0.93, 0.9], "metallic": 1, "roughness": 0.2})")}};
  return t;
}

}  // namespace

std::optional<std::string> builtinSceneJson(const std::string& name) {
  auto it = table().find(name);
  if (it == table().end()) return std::nullopt;
  return it->second;
}

std::string Scene::builtinDescription(const std::string& name) { return builtinSceneJson(name).value_or(""); }

std::vector<std::string> Scene::builtinScenes() {
  std::vector<std::string> names;
  for (const auto& [n, _] : table()) names.push_back(n);
  return names;
}

}  // namespace rtd::render
