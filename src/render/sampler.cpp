// Void-and-cluster blue-noise rank map (Ulichney 1993, "The void-and-cluster method for dither
// array generation"), computed once at first use (about 20 ms for 64 x 64).
#include <algorithm>
#include <array>
#include <cmath>

#include "render/sampler.h"

namespace rtd::render {

namespace {

struct Energy {
  static constexpr int N = kBlueNoiseSize;
  std::vector<float> kernel = std::vector<float>(N * N), energy = std::vector<float>(N * N, 0.0f);
  std::vector<uint8_t> on = std::vector<uint8_t>(N * N, 0);

  Energy() {
    // Toroidal Gaussian, sigma = 1.5 (Ulichney's choice).
    for (int dy = 0; dy < N; ++dy)
      for (int dx = 0; dx < N; ++dx) {
        const int x = std::min(dx, N - dx), y = std::min(dy, N - dy);
        kernel[dy * N + dx] = std::exp(-float(x * x + y * y) / (2.0f * 1.5f * 1.5f));
      }
  }
  void toggle(int p, bool value) {
    on[p] = value;
    const float s = value ? 1.0f : -1.0f;
    const int px = p % N, py = p / N;
    for (int y = 0; y < N; ++y)
      for (int x = 0; x < N; ++x) energy[y * N + x] += s * kernel[((y - py + N) % N) * N + (x - px + N) % N];
  }
  /// Tightest cluster: the set pixel with the highest energy. Largest void: the unset pixel with
  /// the lowest energy. Ties go to the lowest index (deterministic).
  int tightestCluster() const {
    int best = -1;
    for (int i = 0; i < N * N; ++i)
      if (on[i] && (best < 0 || energy[i] > energy[best])) best = i;
    return best;
  }
  int largestVoid() const {
    int best = -1;
    for (int i = 0; i < N * N; ++i)
      if (!on[i] && (best < 0 || energy[i] < energy[best])) best = i;
    return best;
  }
};

std::vector<uint16_t> makeRanks() {
  constexpr int N = kBlueNoiseSize, total = N * N;
  Energy e;
  // Initial pattern: 10% of the pixels from a fixed hash, then relax (swap the tightest cluster
  // into the largest void) until stable.
  const int initial = total / 10;
  for (int k = 0, placed = 0; placed < initial; ++k) {
    const int p = int(hash32(uint32_t(k) * 2654435761U + 12345U) % uint32_t(total));
    if (!e.on[p]) {
      e.toggle(p, true);
      ++placed;
    }
  }
  for (int iter = 0; iter < 10 * total; ++iter) {
    const int c = e.tightestCluster();
    e.toggle(c, false);
    const int v = e.largestVoid();
    if (v == c) {
      e.toggle(c, true);
      break;
    }
    e.toggle(v, true);
  }
  std::vector<uint16_t> rank(total, 0);
  const std::vector<uint8_t> prototype = e.on;
  const std::vector<float> prototypeEnergy = e.energy;
  // Phase 1: remove the tightest cluster one at a time, ranks counting down.
  for (int r = initial - 1; r >= 0; --r) {
    const int c = e.tightestCluster();
    e.toggle(c, false);
    rank[c] = uint16_t(r);
  }
  // Phases 2 and 3: from the prototype, fill the largest void one at a time, ranks counting up.
  e.on = prototype;
  e.energy = prototypeEnergy;
  for (int r = initial; r < total; ++r) {
    const int v = e.largestVoid();
    e.toggle(v, true);
    rank[v] = uint16_t(r);
  }
  return rank;
}

}  // namespace

uint32_t sobol1(uint32_t index) {
  // Column k of the generator matrix is the k-th direction number of Sobol's second dimension
  // (primitive polynomial x + 1: v_k = v_{k-1} ^ (v_{k-1} >> 1), v_0 = 2^31).
  static const auto tables = [] {
    std::array<uint32_t, 32> column{};
    uint32_t v = 1U << 31;
    for (int k = 0; k < 32; ++k, v ^= v >> 1) column[k] = v;
    std::array<std::array<uint32_t, 256>, 4> t{};
    for (int byte = 0; byte < 4; ++byte)
      for (int b = 0; b < 256; ++b) {
        uint32_t r = 0;
        for (int k = 0; k < 8; ++k)
          if (b & (1 << k)) r ^= column[byte * 8 + k];
        t[byte][b] = r;
      }
    return t;
  }();
  return tables[0][index & 255] ^ tables[1][(index >> 8) & 255] ^ tables[2][(index >> 16) & 255] ^ tables[3][index >> 24];
}

const std::vector<uint16_t>& blueNoiseRanks() {
  static const std::vector<uint16_t> ranks = makeRanks();
  return ranks;
}

}  // namespace rtd::render
