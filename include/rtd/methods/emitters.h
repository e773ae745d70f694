// rtdenoise — settings of the emitter exclusion that SVGF and BMFR share (issue 12, the emitter
// halo; docs/methods/svgf.md and bmfr.md, "Emitters").
#pragma once
#include "rtd/settings_visit.h"

namespace rtd {

/// Pixels whose primary hit is an emitter (Buffer::Emission's largest channel above
/// emitterThreshold) are left out of the spatial filter: they weigh 0 as neighbours and take
/// no neighbour's light (SVGF: a-trous levels and spatial-variance window; BMFR: the block
/// fits, and such a pixel's output is its own accumulated value). Their emission is separated
/// at import and added back exactly anyway (core/frame_data.h subtractEmissionRow); what the
/// filter would spread is the lamp's own reflected light, which the features cannot tell from
/// the surface it is mounted on (a lamp 5 mm below a ceiling has the ceiling's normal and
/// depth). Frames without Buffer::Emission, or without any pixel above the threshold, are
/// unaffected (the output is bit-identical with the setting on and off).
/// SVGF with the setting off still leaves out the emitter pixels whose albedo exceeds 1 in a
/// channel (Blender's Denoising Albedo of an emissive surface is its emission): such a pixel
/// reflects nothing, so like a sky pixel it has nothing to filter (docs/methods/svgf.md).
struct EmitterSettings {
  /// On in BMFR, off in SVGF (each method's settings say why).
  bool excludeEmitters = true;
  /// Emission (radiance, per channel) a pixel must exceed to count as an emitter. 0: any
  /// emission. Raise it to keep dim emissive surfaces (a glowing panel) filtered.
  float emitterThreshold = 0.0f;

  template <class V> void visit(V& v) {
    v("excludeEmitters", excludeEmitters,
      "emitter pixels (emission > emitterThreshold) weigh 0 as neighbours and take none in the spatial filter "
      "(SVGF a-trous and variance window, BMFR fits: output = own accumulated value); their reflected light "
      "otherwise bleeds into the surface around a lamp (issue 12); SVGF with it off still leaves out emitters of "
      "albedo > 1 (no reflectance, as Blender writes them)");
    v("emitterThreshold", emitterThreshold, "emission (largest channel, radiance) above which a pixel is an emitter; 0 = any",
      Range{0, 1e9});
  }
};

}  // namespace rtd
