// Edge-stopping weights of the a-trous filter (Schied et al. 2017 Eq. 3), shared by the
// variance estimate and the a-trous levels. Twins of depthWeight/normalWeight in
// src/passes/atrous.h.

// Weights below 2^-24 count as exactly 0, as on the CPU: an a-trous tap's h w_z w_n w_l, the
// variance estimate's w_z w_n (src/core/flush.h: the CPU's arithmetic never produces
// subnormals; the bound is shared so both backends reject the same taps).
const float kMinWeight = 5.9604644775390625e-8;  // 2^-24
float cutWeight(float w) { return w >= kMinWeight ? w : 0.0; }

// max(0, c)^e by binary exponentiation: for e = 2^k exactly k squarings, as on the CPU.
float normalWeight(float cosine, int e) {
  float d = max(cosine, 0.0), r = 1.0;
  while (true) {
    if ((e & 1) != 0) r *= d;
    e >>= 1;
    if (e == 0) return r;
    d *= d;
  }
}
