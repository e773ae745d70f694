// rtdenoise — method "bmfr": Blockwise Multi-Order Feature Regression (Koskela et al. 2019,
// ACM TOG 38(5)). Phase I accumulates the noisy 1-spp illumination, phase II fits each block
// of it as a least-squares combination of noise-free features [1, n, w, w^2] (augmented
// Householder QR with stochastic regularization), phase III accumulates the fit again and
// applies TAA. See docs/methods/bmfr.md for every choice where the paper is unclear.
#pragma once
#include "rtd/methods/emitters.h"
#include "rtd/methods/reprojection.h"
#include "rtd/methods/taa.h"

namespace rtd {

/// Side of the square fitting blocks.
enum class BmfrBlockSize { Block32, Block64 };

struct BmfrSettings {
  static constexpr const char* kMethod = "bmfr";

  /// Phase I new-sample weight floor: w = max(1/n, alphaNoisy), a cumulative average that
  /// becomes an 80/20 exponential average (Koskela et al. 2019 Sec. 4.1).
  float alphaNoisy = 0.2f;
  /// Phase III new-sample weight floor: w = max(1/n, alphaFiltered), n being phase I's sample
  /// count (Koskela et al. 2019 Sec. 4.3: "10% of new data"; [CODE] reuses the phase I count).
  float alphaFiltered = 0.1f;
  /// Sample-count cap: the paper stores 8-bit counts (Sec. 5), so 255.
  int maxHistoryLength = 255;
  /// Divide radiance by the first-bounce albedo before filtering, multiply after (Sec. 3).
  bool demodulate = true;

  /// Block side: 32 (the paper's fast choice, Sec. 4.2) or 64 (its best quality; Higginson's default).
  BmfrBlockSize blockSize = BmfrBlockSize::Block32;
  /// Displace the block grid every frame with the static 16-entry offset sequence (Sec. 4.2;
  /// the values are the authors' code's, scaled by blockSize / 32).
  bool blockOffsets = true;
  /// Rows of the least-squares problem per block: 0 = every pixel of the block (the paper);
  /// otherwise this many jittered-stratified samples (Higginson Sec. 3.2: 36 with 64x64 blocks).
  int samplesPerBlock = 0;
  /// Amplitude epsilon of the uniform regularization noise on [-eps, eps] added to the
  /// normalized features before the QR (Sec. 4.2: 0.01 "worked with all our tested scenes").
  float noiseAmount = 0.01f;

  /// Feature set. The constant 1 is always present; the paper's set is [1, n, w, w^2] (Sec. 5).
  bool featureNormal = true;
  bool featurePosition = true;
  bool featurePositionSquared = true;
  /// Material id (Fig. 10 of the paper) and roughness (Sec. 7): used when the frame has them.
  bool featureMaterialId = false;
  bool featureRoughness = false;

  /// Stage switches (the reference code's debug toggles): phase II fit (off: the accumulated
  /// noisy input passes through) and phase III accumulation.
  bool fit = true;
  bool accumulateFiltered = true;

  /// Emitter pixels weigh 0 in the block fits and keep their own phase I value instead of the
  /// fit's (issue 12; docs/methods/bmfr.md, "Emitters"). On: the sky (whose radiance is its
  /// emission) and lamps no longer enter the fits of the surfaces next to them.
  EmitterSettings emitters;

  /// Phase I/III reprojection: BMFR tests only world position and shading normal per tap.
  /// The authors' position limit is an absolute 0.04 (Sponza, sqrt(0.0016)), right for one
  /// scene's scale only; the default here is scale-free, 4 pixel footprints (positionFootprints;
  /// positionTolerance=0.04 positionFootprints=0 restores the authors' test). normalTolerance
  /// 0.875 is |dn|^2 < 0.25 for unit normals.
  /// The depth and object-id tests and the 3x3 fallback are off.
  ReprojectionSettings reprojection = defaultReprojection();
  /// Final TAA; the authors' code blends 20% of the current frame.
  TaaSettings taa = defaultTaa();

  static ReprojectionSettings defaultReprojection() {
    ReprojectionSettings s;
    s.testDepth = false;
    s.normalTolerance = 0.875f;
    s.testObjectId = false;
    s.positionTolerance = 0.0f;   // scale-free instead of the authors' 0.04 m (see reprojection.h)
    s.positionFootprints = 4.0f;
    s.fallback3x3 = false;
    return s;
  }
  static TaaSettings defaultTaa() {
    TaaSettings s;
    s.taa = true;
    s.taaAlpha = 0.2f;
    s.taaNeighbourhood = TaaNeighbourhood::boxCross;  // the BMFR code's bounds
    // Constant alpha: BMFR's output keeps per-block noise that its TAA hides; a weight that
    // rises with the subpixel offset shows it (Blender glossy fixture: -0.4 dB, temporal error
    // 0.040 -> 0.072 at 2; docs/methods/taa.md, "Subpixel alpha").
    s.taaSubpixelAlpha = 0.0f;
    return s;
  }

  template <class V> void visit(V& v) {
    v("alphaNoisy", alphaNoisy, "phase I new-sample weight floor, max(1/n, a) (BMFR: 0.2)", Range{0.001, 1});
    v("alphaFiltered", alphaFiltered, "phase III new-sample weight floor, max(1/n, a) (BMFR: 0.1)", Range{0.001, 1});
    v("maxHistoryLength", maxHistoryLength, "sample-count cap (BMFR: 8-bit, 255)", Range{1, 255});
    v("demodulate", demodulate, "divide by albedo before filtering, multiply after");
    v("blockSize", blockSize, "fitting block side (BMFR: 32; best quality 64)", {"32", "64"});
    v("blockOffsets", blockOffsets, "displace the block grid with the 16-frame offset sequence");
    v("samplesPerBlock", samplesPerBlock, "least-squares rows per block, 0 = all pixels (Higginson: 36)", Range{0, 4096});
    v("noiseAmount", noiseAmount, "stochastic regularization amplitude eps, noise U[-eps, eps] (BMFR: 0.01)", Range{0, 10});
    v("featureNormal", featureNormal, "fit on the shading normal n (3 features)");
    v("featurePosition", featurePosition, "fit on the world position w (3 features)");
    v("featurePositionSquared", featurePositionSquared, "fit on w^2 per axis (3 features, BMFR's multi-order term)");
    v("featureMaterialId", featureMaterialId, "fit on the material id when the frame has it");
    v("featureRoughness", featureRoughness, "fit on the roughness when the frame has it");
    v("fit", fit, "run the phase II fit (off: pass the accumulated input through)");
    v("accumulateFiltered", accumulateFiltered, "run the phase III accumulation of the fit");
    emitters.visit(v);
    reprojection.visit(v);
    taa.visit(v);
  }
};

}  // namespace rtd
