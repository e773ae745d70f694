#version 450
// Pass "fit" of BMFR (Koskela et al. 2019 Sec. 4.2): one workgroup per block of the displaced
// grid. Gathers the block's rows (every pixel, mirrored at the image borders, or
// `samplesPerBlock` jittered-stratified ones), normalizes every feature to [-1, 1] over the
// block, adds the per-frame regularization noise, factors [T + N, z_R, z_G, z_B] with Householder
// reflections keeping only R (Eqs. 4-7), and back-substitutes the three channels' weights.
// With excludeEmitters the rows of emitter pixels weigh 0 (issue 12, weighEmitterRows).
// Port of BmfrCpu::fitBlock and bmfr::householderQr / backSubstitute (src/methods/bmfr/).
//
// The block matrix lives in a device buffer (`scratch`, column-major per block: column c, row r
// at c * rows + r), because 1024-4096 rows x 15 columns exceed the 16 KiB of shared memory
// Vulkan guarantees. Thread t owns rows t, t + 256, ...: it only ever reads back what it wrote
// itself (neighbouring threads touch neighbouring addresses: coalesced), and the only values
// exchanged between threads go through shared memory: the reductions (feature ranges, column
// norms and dot products) and the pivot row of each reflection.
#include "common.glsl"

#define WG 256u
#define HALF 128u
layout(local_size_x = 256, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer Noisy { float noisy[]; };  // phase I colour: planes 0-2
layout(std430, binding = 1) readonly buffer Normals { float normals[]; };
layout(std430, binding = 2) readonly buffer Positions { float positions[]; };
layout(std430, binding = 3) readonly buffer MaterialIds { float materialIds[]; };
layout(std430, binding = 4) readonly buffer Roughness { float roughnessPlane[]; };
layout(std430, binding = 5) buffer Scratch { float scratch[]; };
layout(std430, binding = 6) writeonly buffer Fits { float fits[]; };
layout(std430, binding = 7) readonly buffer Emission { float emission[]; };

#include "bmfr.glsl"

layout(push_constant) uniform PC {
  uint width, height;
  int originX, originY;  // block (bx, by) covers [origin + b * size, origin + (b + 1) * size)
  uint blocksX, size;
  uint rows;         // least-squares rows per block
  uint features;     // M, the constant included
  uint blockBase;    // grid index of this dispatch's first block (the scratch binding starts there)
  uint blockStride;  // floats per block in `scratch`
  uint frameIndex;   // frames since the last reset: the noise and the samples change every frame
  float noise;       // amplitude eps of the uniform noise (already scaled for sub-sampled blocks); 0: none
  uvec4 codes;       // feature codes (bmfr.glsl)
  float emitterThreshold;
  uint excludeEmitters;  // 1: emitter rows weigh 0 (the frame has Buffer::Emission)
} pc;

// Reductions: 2 x 12 values (feature minima and maxima) or 15 (dot products) per thread; the
// upper half of the workgroup folds into the lower half first, so 128 slots per value suffice
// (12 KiB: with R and the pivot row the shader stays below the 16 KiB Vulkan guarantees).
#define RED_VALUES (2 * BMFR_MAX_FEATURES)
shared float red[RED_VALUES * HALF];
shared float pivotRow[BMFR_MAX_COLUMNS];
shared float R[BMFR_MAX_FEATURES * BMFR_MAX_COLUMNS];  // R (columns < M) and r (columns M..M+2)

#define REDUCE_SUM 0u
#define REDUCE_MIN_MAX 1u  // values [0, half) reduce by min, [half, 2 half) by max

float combine(uint mode, uint j, uint half_, float a, float b) {
  if (mode == REDUCE_SUM) return a + b;
  return j < half_ ? min(a, b) : max(a, b);
}

// Reduces v[0..count) over the workgroup; the results are in red[j * HALF] afterwards.
void reduce(float v[RED_VALUES], uint count, uint mode, uint half_) {
  const uint t = gl_LocalInvocationID.x;
  if (t >= HALF)
    for (uint j = 0; j < count; ++j) red[j * HALF + t - HALF] = v[j];
  barrier();
  if (t < HALF)
    for (uint j = 0; j < count; ++j) red[j * HALF + t] = combine(mode, j, half_, v[j], red[j * HALF + t]);
  barrier();
  for (uint s = HALF / 2u; s > 0u; s >>= 1u) {
    if (t < s)
      for (uint j = 0; j < count; ++j)
        red[j * HALF + t] = combine(mode, j, half_, red[j * HALF + t], red[j * HALF + t + s]);
    barrier();
  }
}

uint scratchIndex(uint base, uint column, uint row) { return base + column * pc.rows + row; }

// The image pixel of least-squares row r (BmfrCpu::blockPixels).
uint pixelOfRow(uint r, int x0, int y0, uint block, bool sampled, uint cellsX, uint cellsY) {
  const int size = int(pc.size), w = int(pc.width), h = int(pc.height);
  int lx, ly;
  if (!sampled) {
    ly = int(r / pc.size);
    lx = int(r % pc.size);
  } else {
    // Jittered stratification: one hashed jitter per sample, block and frame.
    const float jx = hashUniform(r, block, pc.frameIndex * 2u);
    const float jy = hashUniform(r, block, pc.frameIndex * 2u + 1u);
    precise float fx = (float(r % cellsX) + jx) * float(size) / float(cellsX);
    precise float fy = (float(r / cellsX) + jy) * float(size) / float(cellsY);
    lx = min(int(fx), size - 1);
    ly = min(int(fy), size - 1);
  }
  return uint(mirrorIndex(y0 + ly, h)) * pc.width + uint(mirrorIndex(x0 + lx, w));
}

// The block's normalization of one feature (bmfr_simd.cpp normalization()): (f - centre) *
// scale spans [-1, 1]; a feature constant on the block to rounding (half range at most
// BMFR_CONSTANT_FEATURE of `magnitude`: its own largest |f|, or its vector's for n and w)
// becomes a zero column.
void normalization(float lo, float hi, float magnitude, out float centre, out float scale) {
  centre = 0.5 * (lo + hi);
  const float halfRange = 0.5 * (hi - lo);
  scale = halfRange > BMFR_CONSTANT_FEATURE * max(magnitude, 1e-30) ? 1.0 / halfRange : 0.0;
}

void main() {
  const uint t = gl_LocalInvocationID.x;
  const uint block = pc.blockBase + gl_WorkGroupID.x;
  const uint bx = block % pc.blocksX, by = block / pc.blocksX;
  const int x0 = pc.originX + int(bx * pc.size), y0 = pc.originY + int(by * pc.size);
  const int size = int(pc.size);
  // Blocks that hold no image pixel are skipped (the whole workgroup returns: uniform).
  if (x0 + size <= 0 || x0 >= int(pc.width) || y0 + size <= 0 || y0 >= int(pc.height)) return;

  const uint plane = pc.width * pc.height, M = pc.features, C = M + 3u, rows = pc.rows;
  const uint base = gl_WorkGroupID.x * pc.blockStride;
  const bool sampled = rows != pc.size * pc.size;
  uint cellsX = 1u;
  while (cellsX * cellsX < rows) ++cellsX;
  const uint cellsY = (rows + cellsX - 1u) / cellsX;
  const float kInf = uintBitsToFloat(0x7f800000u);
  uint codes[BMFR_MAX_FEATURES];
  for (uint k = 0; k < M; ++k) codes[k] = featureCode(pc.codes, k);

  // 1. Raw feature columns and colour columns; each feature's range over the rows (and, for
  //    sub-sampled blocks, over every image pixel of the block, so the synthesis never meets a
  //    feature outside [-1, 1]).
  float v[RED_VALUES];
  for (uint k = 0; k < M; ++k) { v[k] = kInf; v[M + k] = -kInf; }
  float emitterRows = 0.0;
  for (uint r = t; r < rows; r += WG) {
    const uint i = pixelOfRow(r, x0, y0, block, sampled, cellsX, cellsY);
    if (pc.excludeEmitters != 0u && emitterAt(i, plane, pc.emitterThreshold)) emitterRows += 1.0;
    for (uint k = 1; k < M; ++k) {
      const float f = rawFeature(codes[k], i, plane);
      scratch[scratchIndex(base, k, r)] = f;
      v[k] = min(v[k], f);
      v[M + k] = max(v[M + k], f);
    }
    for (uint c = 0; c < 3u; ++c) scratch[scratchIndex(base, M + c, r)] = noisy[c * plane + i];
  }
  const int bx0 = max(x0, 0), bx1 = min(x0 + size, int(pc.width)), by0 = max(y0, 0), by1 = min(y0 + size, int(pc.height));
  const uint bw = uint(bx1 - bx0), pixels = bw * uint(by1 - by0);
  if (sampled)
    for (uint q = t; q < pixels; q += WG) {
      const uint i = uint(by0 + int(q / bw)) * pc.width + uint(bx0 + int(q % bw));
      for (uint k = 1; k < M; ++k) {
        const float f = rawFeature(codes[k], i, plane);
        v[k] = min(v[k], f);
        v[M + k] = max(v[M + k], f);
      }
    }
  reduce(v, 2u * M, REDUCE_MIN_MAX, M);

  float centre[BMFR_MAX_FEATURES], scale[BMFR_MAX_FEATURES], positionCentre[3];
  centre[0] = 0.0;
  scale[0] = 1.0;
  bool squares = false;
  // The channels of n and w are judged against their vector's magnitude on the block (the
  // squares' raw columns hold w).
  float normalMagnitude = 0.0, positionMagnitude = 0.0;
  for (uint k = 1; k < M; ++k) {
    const float m = max(abs(red[k * HALF]), abs(red[(M + k) * HALF]));
    const uint kind = featureKind(codes[k]);
    if (kind == BMFR_NORMAL) normalMagnitude = max(normalMagnitude, m);
    if (kind == BMFR_POSITION || kind == BMFR_POSITION_SQUARED) positionMagnitude = max(positionMagnitude, m);
  }
  for (uint k = 1; k < M; ++k) {
    const float lo = red[k * HALF], hi = red[(M + k) * HALF];
    const uint kind = featureKind(codes[k]);
    // A square's scale is first w's: 0 when w is constant, and then the square is too.
    const float magnitude = kind == BMFR_NORMAL ? normalMagnitude
                            : kind == BMFR_POSITION || kind == BMFR_POSITION_SQUARED ? positionMagnitude
                                                                                      : max(abs(lo), abs(hi));
    normalization(lo, hi, magnitude, centre[k], scale[k]);
    if (kind == BMFR_POSITION_SQUARED) {
      // Squares about the block's position mid-range: same span as w^2 with 1 and w.
      positionCentre[featureChannel(codes[k])] = 0.5 * (lo + hi);
      squares = true;
    }
  }
  barrier();  // every thread has read the ranges before `red` is reused

  // Issue 12: the rows of emitter pixels weigh 0, unless every row is one (weighEmitterRows).
  bool weighEmitters = false;
  if (pc.excludeEmitters != 0u) {
    v[0] = emitterRows;
    reduce(v, 1u, REDUCE_SUM, 0u);
    weighEmitters = red[0] > 0.0 && red[0] < float(rows);
    barrier();
  }

  // 2. (w - c)^2 columns and their range.
  if (squares) {
    for (uint k = 0; k < M; ++k) { v[k] = kInf; v[M + k] = -kInf; }
    for (uint r = t; r < rows; r += WG)
      for (uint k = 1; k < M; ++k) {
        if (featureKind(codes[k]) != BMFR_POSITION_SQUARED) continue;
        const uint s = scratchIndex(base, k, r);
        precise float d = scratch[s] - positionCentre[featureChannel(codes[k])];
        precise float sq = d * d;
        scratch[s] = sq;
        v[k] = min(v[k], sq);
        v[M + k] = max(v[M + k], sq);
      }
    if (sampled)
      for (uint q = t; q < pixels; q += WG) {
        const uint i = uint(by0 + int(q / bw)) * pc.width + uint(bx0 + int(q % bw));
        for (uint k = 1; k < M; ++k) {
          if (featureKind(codes[k]) != BMFR_POSITION_SQUARED) continue;
          precise float d = rawFeature(codes[k], i, plane) - positionCentre[featureChannel(codes[k])];
          precise float sq = d * d;
          v[k] = min(v[k], sq);
          v[M + k] = max(v[M + k], sq);
        }
      }
    reduce(v, 2u * M, REDUCE_MIN_MAX, M);
    for (uint k = 1; k < M; ++k)
      if (featureKind(codes[k]) == BMFR_POSITION_SQUARED) {
        const float lo = red[k * HALF], hi = red[(M + k) * HALF];
        if (scale[k] != 0.0) normalization(lo, hi, max(abs(lo), abs(hi)), centre[k], scale[k]);
        else centre[k] = 0.0;
      }
  }

  // 3. Normalize to [-1, 1] and add the noise to T only (Eq. 7): uniform on [-eps, eps] per
  //    (row, feature), the same in every block of a frame (BmfrCpu::makeNoise).
  //    A weighed-out emitter row becomes 0 in every column, the colour's included.
  for (uint r = t; r < rows; r += WG) {
    const bool drop =
        weighEmitters && emitterAt(pixelOfRow(r, x0, y0, block, sampled, cellsX, cellsY), plane, pc.emitterThreshold);
    scratch[scratchIndex(base, 0u, r)] = drop ? 0.0 : 1.0;
    for (uint k = 1; k < M; ++k) {
      const uint s = scratchIndex(base, k, r);
      precise float f = (scratch[s] - centre[k]) * scale[k];
      if (pc.noise > 0.0) {
        precise float n = pc.noise * (2.0 * hashUniform(r, k, pc.frameIndex) - 1.0);
        f += n;
      }
      scratch[s] = drop ? 0.0 : f;
    }
    if (drop)
      for (uint c = 0; c < 3u; ++c) scratch[scratchIndex(base, M + c, r)] = 0.0;
  }

  // 4. Householder QR of the C = M + 3 columns, R only. Reflection k maps rows k.. of column k
  //    onto -sign(x_k) ||x|| e_k (u_k = x_k + sign(x_k) ||x|| never cancels) and is applied to
  //    every later column, the colour columns included, so they end up holding r = Q^T z.
  //    One reduction per reflection gives ||x_below||^2 and every x_below . y_j at once; the
  //    pivot row's entries come through shared memory from the thread that owns it.
  for (uint k = 0; k < M; ++k) {
    barrier();  // the previous reflection's results have been read by every thread
    if (k >= rows) {  // fewer rows than features: nothing left below the diagonal
      if (t == 0u)
        for (uint j = k; j < C; ++j) R[k * BMFR_MAX_COLUMNS + j] = 0.0;
      continue;
    }
    const uint n = C - k;
    for (uint j = 0; j < n; ++j) v[j] = 0.0;
    for (uint r = t; r < rows; r += WG) {
      if (r < k) continue;
      if (r == k) {
        for (uint j = k; j < C; ++j) pivotRow[j] = scratch[scratchIndex(base, j, r)];
        continue;
      }
      const float x = scratch[scratchIndex(base, k, r)];
      for (uint j = 0; j < n; ++j) v[j] += x * scratch[scratchIndex(base, k + j, r)];
    }
    reduce(v, n, REDUCE_SUM, 0u);
    const float below = red[0], xk = pivotRow[k];
    if (below == 0.0) {  // already upper triangular in this column (or all zero: R_kk = 0)
      if (t == 0u)
        for (uint j = k; j < C; ++j) R[k * BMFR_MAX_COLUMNS + j] = pivotRow[j];
      continue;
    }
    const float norm = sqrt(below + xk * xk);
    const float alpha = xk >= 0.0 ? -norm : norm;
    const float uk = xk - alpha;
    const float beta = 2.0 / (below + uk * uk);
    float s[BMFR_MAX_COLUMNS];
    for (uint j = k + 1u; j < C; ++j) s[j] = beta * (red[(j - k) * HALF] + uk * pivotRow[j]);
    if (t == 0u) {
      R[k * BMFR_MAX_COLUMNS + k] = alpha;
      for (uint j = k + 1u; j < C; ++j) R[k * BMFR_MAX_COLUMNS + j] = pivotRow[j] - s[j] * uk;
    }
    for (uint r = t; r < rows; r += WG) {
      if (r <= k) continue;
      const float x = scratch[scratchIndex(base, k, r)];
      for (uint j = k + 1u; j < C; ++j) {
        const uint y = scratchIndex(base, j, r);
        scratch[y] -= s[j] * x;
      }
    }
  }
  barrier();

  // 5. Back substitution R alpha = r per channel (bmfr::backSubstitute): a pivot at or below
  //    1e-5 of the largest counts as rank-deficient and gets weight 0.
  const uint fit = block * BMFR_FIT_STRIDE;
  if (t < 3u) {
    float maxPivot = 0.0;
    for (uint k = 0; k < M; ++k) maxPivot = max(maxPivot, abs(R[k * BMFR_MAX_COLUMNS + k]));
    const float tolerance = 1e-5 * maxPivot;
    float a[BMFR_MAX_FEATURES];
    for (int k = int(M) - 1; k >= 0; --k) {
      const float pivot = R[k * BMFR_MAX_COLUMNS + k];
      if (!(abs(pivot) > tolerance)) {
        a[k] = 0.0;
        continue;
      }
      precise float value = R[k * BMFR_MAX_COLUMNS + M + t];
      for (uint j = uint(k) + 1u; j < M; ++j) value -= R[k * BMFR_MAX_COLUMNS + j] * a[j];
      a[k] = value / pivot;
    }
    for (uint k = 0; k < M; ++k) fits[fit + t * BMFR_MAX_FEATURES + k] = a[k];
  }
  if (t == 3u) {
    for (uint k = 0; k < M; ++k) {
      fits[fit + BMFR_FIT_CENTRE + k] = centre[k];
      fits[fit + BMFR_FIT_SCALE + k] = scale[k];
    }
    for (uint c = 0; c < 3u; ++c) fits[fit + BMFR_FIT_POSITION_CENTRE + c] = squares ? positionCentre[c] : 0.0;
  }
}
