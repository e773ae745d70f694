// rtdenoise — method "rae": the recurrent denoising autoencoder of Chaitanya et al. (2017), as
// Higginson's thesis (2023, Sec. 2.1, 3.4) describes and compares it: a U-shaped network of
// 3x3 convolutions with 2x max-pooling and bilinear upsampling, a recurrent block at each
// encoder level carrying its hidden state from frame to frame, and the albedo and normal
// concatenated at each decoder block. Trained here (python/rtdenoise_train, the data set of
// `rtdenoise dataset`); the CPU path runs on oneDNN. docs/methods/rae.md has the architecture,
// the weights file format, the training and the evaluation.
#pragma once
#include <string>

#include "rtd/methods/reprojection.h"

namespace rtd {

struct RaeSettings {
  static constexpr const char* kMethod = "rae";

  /// Weights file (JSON, format "rtdenoise-rae-weights" version 1, docs/methods/rae.md);
  /// empty = the weights built into the library (src/methods/rae/rae_weights.json). The file
  /// fixes the architecture (levels, channels, input set).
  std::string weights;
  /// Carry the hidden states from frame to frame (Chaitanya et al.); off: every frame is
  /// denoised as the first after a reset (the thesis's own, non-recurrent proof of concept).
  bool recurrent = true;
  /// Not a setting: the network reprojects nothing (its state is not warped, as in Chaitanya
  /// et al.). The depth and object-id tests are off so that import copies only the colour,
  /// albedo, normal and emission it needs.
  ReprojectionSettings reprojection = [] {
    ReprojectionSettings r;
    r.testDepth = false;
    r.testObjectId = false;
    return r;
  }();

  template <class V> void visit(V& v) {
    v("weights", weights, "weights file (rtdenoise-rae-weights v1 JSON); empty = built-in weights");
    v("recurrent", recurrent, "carry the encoder's hidden states across frames (off: each frame as a first frame)");
  }
};

}  // namespace rtd
