// TNND's model on the CPU: the weights (file format, built-in default) and the three passes
// encode (frame -> 9-channel state), step (one automaton iteration) and decode (state ->
// radiance). The PyTorch twin is python/rtdenoise_train/models/tnnd.py; the Vulkan twins are
// shaders/tnnd_*.comp. docs/methods/tnnd.md documents the kernels and the file format.
#pragma once
#include <array>
#include <string>

#include "core/frame_data.h"

namespace rtd::tnnd {

constexpr int kState = 9;        ///< [log1p(colour) RGB, view-space normal XYZ, albedo RGB] (Eq. 2.13)
constexpr int kPerception = 39;  ///< s (9), gauss(rgb) (3), laplace (9), sobel x (9), sobel y (9) (Eq. 2.15)
constexpr int kParameters = kPerception * kState + kState;  ///< 351 weights + 9 biases = 360
constexpr const char* kWeightsFormat = "rtdenoise-tnnd-weights";
constexpr int kWeightsVersion = 1;

/// The learned rule: update = sigmoid(p W) + b (Eqs. 2.16-2.17); W row-major [39][9].
struct Weights {
  std::array<float, kPerception * kState> w{};
  std::array<float, kState> b{};
  std::string source;  ///< file name or "built-in", for messages
};

/// Parses a weights file's text (JSON, docs/methods/tnnd.md); throws rtd::Error naming `source`
/// and the field on a wrong format, version, shape or a non-finite value.
Weights parseWeights(const std::string& json, const std::string& source);
/// `path` empty: the built-in weights (src/methods/tnnd/tnnd_weights.json, embedded at build
/// time); otherwise reads and parses the file.
Weights loadWeights(const std::string& path);
/// The JSON text of the built-in weights.
const std::string& builtinWeightsJson();

/// The 9 state planes.
using State = std::array<Plane, kState>;
void resize(State& s, int w, int h);

/// s = [log1p(max(colour, 0)), R n, albedo] (colour: three planes) with R the rotation of camera.worldToCamera (world
/// normals to view space; identity without a valid camera).
void encode(const Plane* color, const std::vector<Plane>& normal, const std::vector<Plane>& albedo, const Camera& camera,
            State& s);
/// One iteration s -> next (s != next): perception with replicated borders, then
/// next = s + sigmoid(p W) + b.
void step(const Weights& weights, const State& s, State& next);
/// The 39-value perception of pixel (x, y), in the order of Eq. 2.15 (tests; step() computes
/// the same values row-wise).
std::array<float, kPerception> perceive(const State& s, int x, int y);
/// Radiance = expm1(max(s_c, 0)) of the first three channels.
void decode(const State& s, Plane3& out);

}  // namespace rtd::tnnd
