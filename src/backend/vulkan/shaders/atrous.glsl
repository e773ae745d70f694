// Edge-stopping weights of the a-trous filter (Schied et al. 2017 Eq. 3), shared by the
// variance estimate and the a-trous levels. Twins of depthWeight/normalWeight in
// src/passes/atrous.h.

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
