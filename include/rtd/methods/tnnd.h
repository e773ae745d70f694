// rtdenoise — method "tnnd": the Tiny Neural Network Denoiser of Higginson's thesis (2023,
// Sec. 2.4), a neural cellular automaton over the 9-channel deep image [log(1 + colour),
// view-space normal, albedo]: each iteration perceives the 3x3 neighbourhood through fixed
// Gaussian, Laplace and Sobel kernels (39 values per pixel) and adds sigmoid(p W) + b with a
// learned 39x9 rule W and bias b (360 parameters). Optionally the colour is temporally
// accumulated first, as in the thesis's pipeline (its Fig. 1.1). docs/methods/tnnd.md has the
// kernels, the weights file format and the training (python/rtdenoise_train).
#pragma once
#include <string>

#include "rtd/methods/reprojection.h"

namespace rtd {

struct TnndSettings {
  static constexpr const char* kMethod = "tnnd";

  /// Automaton iterations per frame. The committed weights were trained with a random count
  /// in [8, 16] per batch (the loss after the last), so any count in that range is stable.
  int iterations = 12;
  /// Weights file (JSON, format "rtdenoise-tnnd-weights" version 1, docs/methods/tnnd.md);
  /// empty = the weights built into the library (src/methods/tnnd/tnnd_weights.json).
  std::string weights;
  /// Temporally accumulate the colour (reprojected, w = max(1/n, alpha)) before the automaton,
  /// the thesis's first accumulation. Off by default: the weights were trained on 1-spp input.
  bool accumulate = false;
  float alpha = 0.2f;
  int maxHistoryLength = 255;
  ReprojectionSettings reprojection;

  template <class V> void visit(V& v) {
    v("iterations", iterations, "automaton iterations per frame (trained with 8..16; Higginson: unstated)", Range{0, 256});
    v("weights", weights, "weights file (rtdenoise-tnnd-weights v1 JSON); empty = built-in weights");
    v("accumulate", accumulate, "temporal accumulation of the colour before the automaton (Higginson Fig. 1.1)");
    v("alpha", alpha, "accumulation: new-sample weight floor, w = max(1/n, alpha)", Range{0.001, 1});
    v("maxHistoryLength", maxHistoryLength, "accumulation: history length cap", Range{1, 65535});
    reprojection.visit(v);
  }
};

}  // namespace rtd
