// The per-pixel reprojection record written by reproject.comp and read by every pass that
// gathers history (the GPU twin of src/passes/reprojection.h). Planes of 32-bit words:
//   0: kind (bits 0-1: 0 none, 1 bilinear, 2 3x3 fallback) | 3x3 valid-tap mask << 2
//   1: base tap index (int): bilinear top-left tap, 3x3 centre
//   2-5: renormalized bilinear weights (float bits)
//   6, 7: reprojected continuous position prevX, prevY (float bits)
#define RP_PLANES 8u
#define RP_NONE 0u
#define RP_BILINEAR 1u
#define RP_FALLBACK 2u

const float kFallbackKernel3x3[9] = float[9](0.0778, 0.1233, 0.0778, 0.1233, 0.1953, 0.1233, 0.0778, 0.1233, 0.0778);

#ifdef RP_GATHER
// The including shader binds the record as `rp` (uint[]) and defines `float histAt(uint j)`
// reading its history plane at element j (a plane offset added by the caller).

uint rpKind(uint i) { return rp[i] & 3u; }

// History value of the plane starting at element `planeBase` for pixel i; 0 where none.
// Same tap order and arithmetic as Reprojection::gather on the CPU.
float gatherPlane(uint i, uint planeBase, uint width, uint plane) {
  const uint km = rp[i];
  const uint kind = km & 3u;
  const int b = int(rp[plane + i]);
  if (kind == RP_BILINEAR) {
    const float w0 = uintBitsToFloat(rp[2u * plane + i]), w1 = uintBitsToFloat(rp[3u * plane + i]);
    const float w2 = uintBitsToFloat(rp[4u * plane + i]), w3 = uintBitsToFloat(rp[5u * plane + i]);
    precise float v = 0.0;
    if (w0 != 0.0) v += w0 * histAt(planeBase + uint(b));
    if (w1 != 0.0) v += w1 * histAt(planeBase + uint(b + 1));
    if (w2 != 0.0) v += w2 * histAt(planeBase + uint(b + int(width)));
    if (w3 != 0.0) v += w3 * histAt(planeBase + uint(b + int(width) + 1));
    return v;
  }
  if (kind == RP_FALLBACK) {
    const uint m = km >> 2;
    precise float sum = 0.0, wsum = 0.0;
    for (int t = 0; t < 9; ++t) {
      if ((m & (1u << t)) == 0u) continue;
      const int j = b + (t / 3 - 1) * int(width) + (t % 3 - 1);
      sum += kFallbackKernel3x3[t] * histAt(planeBase + uint(j));
      wsum += kFallbackKernel3x3[t];
    }
    return sum / wsum;
  }
  return 0.0;
}
#endif
