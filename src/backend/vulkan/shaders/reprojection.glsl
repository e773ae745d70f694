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
// Same tap order and arithmetic as Reprojection::gatherBilinear / taps() on the CPU.
float gatherPlane(uint i, uint planeBase, uint width, uint plane) {
  const uint km = rp[i];
  const uint kind = km & 3u;
  const int b = int(rp[plane + i]);
  if (kind == RP_BILINEAR) {
    // All four taps lie inside the previous frame (reproject slides the footprint inside).
    const float w0 = uintBitsToFloat(rp[2u * plane + i]), w1 = uintBitsToFloat(rp[3u * plane + i]);
    const float w2 = uintBitsToFloat(rp[4u * plane + i]), w3 = uintBitsToFloat(rp[5u * plane + i]);
    precise float v = w0 * histAt(planeBase + uint(b)) + w1 * histAt(planeBase + uint(b + 1)) +
                      w2 * histAt(planeBase + uint(b + int(width))) + w3 * histAt(planeBase + uint(b + int(width) + 1));
    return v;
  }
  if (kind == RP_FALLBACK) {
    // Weights normalized first, then summed, as Reprojection::taps().
    const uint m = km >> 2;
    precise float wsum = 0.0;
    for (int t = 0; t < 9; ++t)
      if ((m & (1u << t)) != 0u) wsum += kFallbackKernel3x3[t];
    precise float v = 0.0;
    for (int t = 0; t < 9; ++t) {
      if ((m & (1u << t)) == 0u) continue;
      const int j = b + (t / 3 - 1) * int(width) + (t % 3 - 1);
      v += (kFallbackKernel3x3[t] / wsum) * histAt(planeBase + uint(j));
    }
    return v;
  }
  return 0.0;
}
#endif

#ifdef RP_BILINEAR_RECORD
// The including shader defines `bool bilinearTapValid(int tx, int ty)` (a tap inside the
// frame). The bilinear footprint of the continuous previous position (px, py) with the taps
// that pass, renormalized and slid inside the frame; false when no tap passes (accepted weight
// <= 1e-4) or the frame is narrower than 2 pixels. Twin of setBilinear (passes/reprojection.h).
bool bilinearRecord(float px, float py, uint width, uint height, out int base, out vec4 wt) {
  base = 0;
  wt = vec4(0.0);
  precise float fx = px - 0.5, fy = py - 0.5;
  if (!(abs(fx) < 1e6 && abs(fy) < 1e6) || width < 2u || height < 2u) return false;
  const int x0 = int(floor(fx)), y0 = int(floor(fy));
  precise float ax = fx - float(x0), ay = fy - float(y0);
  precise float bw[4] = float[4]((1.0 - ax) * (1.0 - ay), ax * (1.0 - ay), (1.0 - ax) * ay, ax * ay);
  const int tx[4] = int[4](x0, x0 + 1, x0, x0 + 1), ty[4] = int[4](y0, y0, y0 + 1, y0 + 1);
  precise float sum = 0.0;
  for (int t = 0; t < 4; ++t)
    if (bw[t] > 0.0 && tx[t] >= 0 && ty[t] >= 0 && tx[t] < int(width) && ty[t] < int(height) &&
        bilinearTapValid(tx[t], ty[t])) {
      wt[t] = bw[t];
      sum += bw[t];
    }
  if (!(sum > 1e-4)) return false;
  for (int t = 0; t < 4; ++t) wt[t] /= sum;
  // Taps outside the image have weight 0: slide the 2x2 window inside (moving the weights
  // with it) so gathers read all four taps without bounds checks.
  int bx = x0, by = y0;
  if (bx < 0) { bx = 0; wt = vec4(wt[1], 0.0, wt[3], 0.0); }
  if (bx > int(width) - 2) { bx = int(width) - 2; wt = vec4(0.0, wt[0], 0.0, wt[2]); }
  if (by < 0) { by = 0; wt = vec4(wt[2], wt[3], 0.0, 0.0); }
  if (by > int(height) - 2) { by = int(height) - 2; wt = vec4(0.0, 0.0, wt[0], wt[1]); }
  base = by * int(width) + bx;
  return true;
}
#endif
