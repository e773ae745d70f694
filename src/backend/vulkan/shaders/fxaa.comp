#version 450
// Pass "fxaa": fast approximate anti-aliasing (Lottes 2009, quality variant), Gersthofer's
// anti-aliasing (Sec. 3.5). Input: R, G, B and FXAA's luma (4 planes); output R, G, B. Port of
// fxaa() (src/passes/fxaa.cpp, which describes the steps): the same decisions in the same
// order, edges clamped.
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer In { float src[]; };
layout(std430, binding = 1) writeonly buffer Out { float outp[]; };

layout(push_constant) uniform PC { uint width, height; float edgeThreshold, edgeThresholdMin, subpixel; } pc;

const float kSteps[12] = float[12](1.0, 1.0, 1.0, 1.0, 1.0, 1.5, 2.0, 2.0, 2.0, 2.0, 4.0, 8.0);

float at(uint c, int x, int y) {
  x = clamp(x, 0, int(pc.width) - 1);
  y = clamp(y, 0, int(pc.height) - 1);
  return src[c * pc.width * pc.height + uint(y) * pc.width + uint(x)];
}
float l(int x, int y) { return at(3u, x, y); }
// Bilinear at continuous pixel coordinates (centres at integers), clamped to the edge.
float bilinear(uint c, float x, float y) {
  const float fx = floor(x), fy = floor(y);
  const float ax = x - fx, ay = y - fy;
  const int x0 = int(fx), y0 = int(fy);
  precise float v = (1.0 - ay) * ((1.0 - ax) * at(c, x0, y0) + ax * at(c, x0 + 1, y0)) +
                    ay * ((1.0 - ax) * at(c, x0, y0 + 1) + ax * at(c, x0 + 1, y0 + 1));
  return v;
}

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const int x = int(p.x), y = int(p.y);
  const uint plane = pc.width * pc.height, i = p.y * pc.width + p.x;
  float sx = 0.0, sy = 0.0;
  const float m = l(x, y), n = l(x, y - 1), s = l(x, y + 1), e = l(x + 1, y), wv = l(x - 1, y);
  const float hi = max(max(max(m, n), max(s, e)), wv), lo = min(min(min(m, n), min(s, e)), wv);
  const float range = hi - lo;
  if (!(range < max(pc.edgeThresholdMin, hi * pc.edgeThreshold))) {
    const float nw = l(x - 1, y - 1), ne = l(x + 1, y - 1), sw = l(x - 1, y + 1), se = l(x + 1, y + 1);
    precise float lowpass = (2.0 * (n + s + e + wv) + (nw + ne + sw + se)) / 12.0;
    const float t = clamp(abs(lowpass - m) / range, 0.0, 1.0);
    const float smoothT = t * t * (3.0 - 2.0 * t);
    const float subpixelShift = smoothT * smoothT * pc.subpixel;
    precise float acrossRows = abs(nw + sw - 2.0 * wv) + 2.0 * abs(n + s - 2.0 * m) + abs(ne + se - 2.0 * e);
    precise float acrossColumns = abs(nw + ne - 2.0 * n) + 2.0 * abs(wv + e - 2.0 * m) + abs(sw + se - 2.0 * s);
    const bool horizontalEdge = acrossRows >= acrossColumns;
    const float l1 = horizontalEdge ? n : wv, l2 = horizontalEdge ? s : e;
    const float g1 = abs(l1 - m), g2 = abs(l2 - m);
    const bool towardsFirst = g1 >= g2;
    const float across = towardsFirst ? -1.0 : 1.0;
    const float edgeMean = 0.5 * (m + (towardsFirst ? l1 : l2));
    const float threshold = 0.25 * max(g1, g2);
    const float ox = horizontalEdge ? 0.0 : 0.5 * across, oy = horizontalEdge ? 0.5 * across : 0.0;
    const float dx = horizontalEdge ? 1.0 : 0.0, dy = horizontalEdge ? 0.0 : 1.0;
    float distNeg = 0.0, distPos = 0.0, endNeg = 0.0, endPos = 0.0;
    bool doneNeg = false, donePos = false;
    for (int k = 0; k < 12; ++k) {
      if (!doneNeg) {
        distNeg += kSteps[k];
        endNeg = bilinear(3u, float(x) + ox - dx * distNeg, float(y) + oy - dy * distNeg) - edgeMean;
        doneNeg = abs(endNeg) >= threshold;
      }
      if (!donePos) {
        distPos += kSteps[k];
        endPos = bilinear(3u, float(x) + ox + dx * distPos, float(y) + oy + dy * distPos) - edgeMean;
        donePos = abs(endPos) >= threshold;
      }
      if (doneNeg && donePos) break;
    }
    const bool negCloser = distNeg < distPos;
    const float endLuma = negCloser ? endNeg : endPos;
    const bool correct = (endLuma < 0.0) != (m - edgeMean < 0.0);
    const float edgeShift = correct ? 0.5 - min(distNeg, distPos) / (distNeg + distPos) : 0.0;
    const float shift = max(edgeShift, subpixelShift);
    if (horizontalEdge) sy = shift * across;
    else sx = shift * across;
  }
  for (uint c = 0; c < 3; ++c)
    outp[c * plane + i] = sx == 0.0 && sy == 0.0 ? src[c * plane + i] : bilinear(c, float(x) + sx, float(y) + sy);
}
