// The RAE's model on the CPU: the weights (file format, built-in default) and the network, run
// with oneDNN's convolutions, pooling and resampling. The PyTorch twin (the definition, and
// the trainer) is python/rtdenoise_train/models/rae.py; docs/methods/rae.md documents the
// architecture and the file format.
//
//   encoder level l (recurrent block):  u_0 = x, u_l = maxpool2(h_{l-1})
//       a_l = act(encIn_l(u_l)),  h_l = act(encRec_l(cat(a_l, h_l^{t-1})))
//   decoder level l = L-2 .. 0:  d_{L-1} = h_{L-1}
//       d_l = decB_l(act(decA_l(cat(up2(d_{l+1}), h_l, f_l))))   (act after decB_l for l > 0)
//
// with x = [log1p(max(c, 0) / (a + eps)), a, n] (the colour demodulated when the albedo is an
// input), f_l the albedo/normal features average-pooled to level l, act = leaky ReLU, up2 =
// bilinear x2 with half-pixel centres. Frames are padded (edges replicated) to a multiple of
// 2^(L-1) and the output cropped; radiance = expm1(clamp(y, 0, 12)) (clamp(a, 0, 1) + eps).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "core/frame_data.h"
#include "rtd/denoiser.h"

namespace rtd::rae {

constexpr const char* kWeightsFormat = "rtdenoise-rae-weights";
constexpr int kWeightsVersion = 1;
/// The network's output y is clamped to [0, kMaxOutput] before expm1 (models/rae.py Y_MAX):
/// radiance stays below e^12 ~ 1.6e5 whatever out-of-domain input does to the activations.
constexpr float kMaxOutput = 12.0f;

/// One 3x3 "same" convolution: weight [out][in][3][3] (PyTorch's layout), bias [out].
struct Conv {
  int out = 0, in = 0;
  std::vector<float> weight, bias;
};

struct Weights {
  bool albedo = true, normal = true;  ///< the input set: colour (+ albedo (+ normal))
  std::vector<int> channels;          ///< C_l per level, L = channels.size() >= 2
  float slope = 0.1f;                 ///< leaky ReLU slope
  float epsilon = 0.01f;              ///< demodulation: colour / (albedo + epsilon)
  std::vector<Conv> encIn, encRec;    ///< L each
  std::vector<Conv> decA, decB;       ///< L - 1 each
  std::string source;                 ///< file name or "built-in", for messages

  int levels() const { return int(channels.size()); }
  int featureChannels() const { return 3 * (int(albedo) + int(normal)); }
  int multiple() const { return 1 << (levels() - 1); }  ///< frames are padded to a multiple of this
  size_t parameters() const;
};

/// Parses a weights file's text (JSON, docs/methods/rae.md); throws rtd::Error naming `source`
/// and the field on a wrong format, version, shape or a non-finite value.
Weights parseWeights(const std::string& json, const std::string& source);
/// `path` empty: the built-in weights (src/methods/rae/rae_weights.json, embedded at build
/// time); otherwise reads and parses the file.
Weights loadWeights(const std::string& path);
/// The input buffers a network with these weights reads: colour, then albedo and normal as its
/// input set has them. The CPU and Vulkan denoisers both answer requiredBuffers() with it.
std::vector<Buffer> requiredBuffers(const Weights& w);
/// The "weights" setting applied by a denoiser: loads `requested` into `w` unless `loaded`
/// already names it and returns true when it did. On an error `requested` goes back to `loaded`
/// (the setting keeps naming the weights in use) and the error propagates.
bool reloadWeights(std::string& requested, std::string& loaded, Weights& w);
/// The JSON text of the built-in weights.
const std::string& builtinWeightsJson();

/// The network for one frame size, with its recurrent state (the hidden states h_l of the
/// previous frame). configure() builds the oneDNN primitives for a size and clears the state.
class Network {
 public:
  Network();
  ~Network();
  Network(const Network&) = delete;
  Network& operator=(const Network&) = delete;

  /// oneDNN's OpenMP threads while configure() and run() execute: at most `threads` (the
  /// denoiser's thread count; 0 = OpenMP's own bound, OMP_NUM_THREADS or the cores), and never
  /// more than OpenMP's own bound. The calling thread's OpenMP setting is restored after.
  void setThreads(int threads);
  void configure(const Weights& weights, int width, int height);
  /// Clears the hidden states: the next frame is denoised as a first frame.
  void reset();
  /// One frame: colour (3 planes, emission taken out), albedo (3) and view-space normal (3)
  /// planes of the configured size (albedo/normal may be null when the weights do not use
  /// them) -> radiance `out`; updates the hidden states. Times each level in `stats`.
  void run(const Plane* color, const Plane* albedo, const Plane* normal, Plane3& out, FrameStats& stats);
  /// Every float the network keeps across frames (the hidden states), for PlaneInspection.
  void forEachState(const std::function<void(const float*, size_t)>& visit) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rtd::rae
