// BMFR's regression core against an independent double-precision least-squares solver
// (normal equations with Cholesky, exact enough in double for well-conditioned blocks).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "methods/bmfr/qr.h"

namespace rtd::bmfr {
namespace {

struct Block {
  int rows, features, channels;
  std::vector<float> cols;  // column-major, stride = rows rounded up to 8 (as householderQr needs)
  size_t stride() const { return size_t(rows + 7) & ~size_t(7); }
  float* col(int c) { return cols.data() + size_t(c) * stride(); }
  const float* col(int c) const { return cols.data() + size_t(c) * stride(); }
  void allocate() { cols.assign(stride() * (features + channels), 0.0f); }
};

// Constant first column, the rest uniform in [-1, 1]; right-hand sides a random combination
// plus uniform noise (so the fit is not exact and the residual is non-trivial).
Block randomBlock(int rows, int features, int channels, uint32_t seed, float noise = 0.3f) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  Block b{rows, features, channels, {}};
  b.allocate();
  for (int r = 0; r < rows; ++r) b.col(0)[r] = 1.0f;
  for (int k = 1; k < features; ++k)
    for (int r = 0; r < rows; ++r) b.col(k)[r] = u(rng);
  for (int c = 0; c < channels; ++c) {
    std::vector<float> a(features);
    for (auto& v : a) v = u(rng);
    for (int r = 0; r < rows; ++r) {
      double z = 0;
      for (int k = 0; k < features; ++k) z += a[k] * b.col(k)[r];
      b.col(features + c)[r] = float(z + noise * u(rng));
    }
  }
  return b;
}

// Solves (T^T T) a = T^T z in double by Cholesky.
std::vector<double> referenceSolve(const Block& b, int channel) {
  const int m = b.features;
  std::vector<double> A(size_t(m) * m), y(m);
  for (int i = 0; i < m; ++i) {
    for (int j = 0; j < m; ++j) {
      double s = 0;
      for (int r = 0; r < b.rows; ++r) s += double(b.col(i)[r]) * b.col(j)[r];
      A[size_t(i) * m + j] = s;
    }
    double s = 0;
    for (int r = 0; r < b.rows; ++r) s += double(b.col(i)[r]) * b.col(m + channel)[r];
    y[i] = s;
  }
  for (int j = 0; j < m; ++j) {  // A = L L^T in place (lower triangle)
    for (int k = 0; k < j; ++k) A[size_t(j) * m + j] -= A[size_t(j) * m + k] * A[size_t(j) * m + k];
    A[size_t(j) * m + j] = std::sqrt(A[size_t(j) * m + j]);
    for (int i = j + 1; i < m; ++i) {
      for (int k = 0; k < j; ++k) A[size_t(i) * m + j] -= A[size_t(i) * m + k] * A[size_t(j) * m + k];
      A[size_t(i) * m + j] /= A[size_t(j) * m + j];
    }
  }
  for (int i = 0; i < m; ++i) {  // L v = y
    for (int k = 0; k < i; ++k) y[i] -= A[size_t(i) * m + k] * y[k];
    y[i] /= A[size_t(i) * m + i];
  }
  for (int i = m - 1; i >= 0; --i) {  // L^T a = v
    for (int k = i + 1; k < m; ++k) y[i] -= A[size_t(k) * m + i] * y[k];
    y[i] /= A[size_t(i) * m + i];
  }
  return y;
}

void solve(Block b, TriangularSystem& system, float alpha[kMaxChannels][kMaxFeatures], int* deficient = nullptr) {
  householderQr(b.cols.data(), b.rows, b.stride(), b.features, b.channels, system);
  const int d = backSubstitute(system, alpha);
  if (deficient) *deficient = d;
}

TEST(BmfrQr, MatchesDoublePrecisionLeastSquares) {
  for (uint32_t seed = 1; seed <= 5; ++seed) {
    const Block b = randomBlock(1024, 10, 3, seed);
    TriangularSystem system;
    float alpha[kMaxChannels][kMaxFeatures];
    int deficient = -1;
    solve(b, system, alpha, &deficient);
    EXPECT_EQ(deficient, 0);
    for (int c = 0; c < 3; ++c) {
      const auto ref = referenceSolve(b, c);
      for (int k = 0; k < 10; ++k) EXPECT_NEAR(alpha[c][k], ref[k], 1e-4 * (1.0 + std::abs(ref[k]))) << "seed " << seed;
    }
  }
}

TEST(BmfrQr, RTransposeRIsTheGramMatrix) {
  // R^T R = (QR)^T QR = T^T T whatever Q is: checks R without needing the reflections.
  const Block b = randomBlock(1024, 10, 3, 11);
  TriangularSystem system;
  float alpha[kMaxChannels][kMaxFeatures];
  solve(b, system, alpha);
  double err = 0, norm = 0;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) {
      double rtr = 0, ttt = 0;
      for (int k = 0; k <= std::min(i, j); ++k) rtr += double(system.R[k][i]) * system.R[k][j];
      for (int r = 0; r < b.rows; ++r) ttt += double(b.col(i)[r]) * b.col(j)[r];
      err += (rtr - ttt) * (rtr - ttt);
      norm += ttt * ttt;
    }
  EXPECT_LT(std::sqrt(err / norm), 1e-5);
  // The stable sign: R_kk = -sign(x_k) ||x||, so R_00 = -sqrt(rows) for the constant column.
  EXPECT_NEAR(system.R[0][0], -32.0f, 1e-4f);
}

TEST(BmfrQr, ResidualIsOrthogonalToTheFeatures) {
  const Block b = randomBlock(1024, 10, 3, 21);
  TriangularSystem system;
  float alpha[kMaxChannels][kMaxFeatures];
  solve(b, system, alpha);
  for (int c = 0; c < 3; ++c) {
    std::vector<double> residual(b.rows);
    double zNorm = 0;
    for (int r = 0; r < b.rows; ++r) {
      double y = 0;
      for (int k = 0; k < 10; ++k) y += double(alpha[c][k]) * b.col(k)[r];
      residual[r] = b.col(10 + c)[r] - y;
      zNorm += double(b.col(10 + c)[r]) * b.col(10 + c)[r];
    }
    for (int k = 0; k < 10; ++k) {
      double d = 0, tNorm = 0;
      for (int r = 0; r < b.rows; ++r) {
        d += b.col(k)[r] * residual[r];
        tNorm += double(b.col(k)[r]) * b.col(k)[r];
      }
      EXPECT_LT(std::abs(d), 1e-5 * std::sqrt(tNorm * zNorm)) << "channel " << c << " feature " << k;
    }
  }
}

TEST(BmfrQr, OneRForThreeChannelsEqualsThreeSeparateSolves) {
  const Block joint = randomBlock(1024, 10, 3, 31);
  TriangularSystem system;
  float alpha[kMaxChannels][kMaxFeatures];
  solve(joint, system, alpha);
  for (int c = 0; c < 3; ++c) {
    Block single{joint.rows, joint.features, 1, {}};
    single.allocate();
    for (int k = 0; k < 10; ++k) std::copy_n(joint.col(k), joint.rows, single.col(k));
    std::copy_n(joint.col(10 + c), joint.rows, single.col(10));
    TriangularSystem s1;
    float a1[kMaxChannels][kMaxFeatures];
    solve(single, s1, a1);
    for (int k = 0; k < 10; ++k) EXPECT_NEAR(a1[0][k], alpha[c][k], 1e-6f * (1.0f + std::abs(alpha[c][k])));
  }
}

TEST(BmfrQr, TiledFactorizationGivesTheSameSolution) {
  for (int rows : {1024, 1000, 4096}) {
    const Block b = randomBlock(rows, 10, 3, 61);
    TriangularSystem plain, tiled;
    float a[kMaxChannels][kMaxFeatures], at[kMaxChannels][kMaxFeatures];
    solve(b, plain, a);
    // Re-lay the block as tiles of 256 rows (the last one partial for 1000 rows).
    const int tileRows = 256, tiles = (rows + tileRows - 1) / tileRows, columns = 13;
    std::vector<float> t(size_t(tiles) * columns * tileRows, 0.0f);
    for (int c = 0; c < columns; ++c)
      for (int r = 0; r < rows; ++r) t[(size_t(r / tileRows) * columns + c) * tileRows + r % tileRows] = b.col(c)[r];
    householderQrTiled(t.data(), rows, tileRows, tileRows, 10, 3, tiled);
    backSubstitute(tiled, at);
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 10; ++k) EXPECT_NEAR(at[c][k], a[c][k], 2e-5f * (1.0f + std::abs(a[c][k]))) << rows;
    for (int i = 0; i < 10; ++i)  // same R up to row signs
      for (int j = i; j < 10; ++j) EXPECT_NEAR(std::abs(tiled.R[i][j]), std::abs(plain.R[i][j]), 1e-4f * std::abs(plain.R[0][0]));
  }
}

TEST(BmfrQr, RecoversAnExactCombination) {
  Block b = randomBlock(1024, 10, 1, 41, 0.0f);
  // z = T a* exactly (up to the float rounding of z itself).
  const float truth[10] = {0.5f, -1.0f, 2.0f, 0.25f, 0.0f, 3.0f, -0.75f, 1.5f, 0.1f, -2.0f};
  for (int r = 0; r < b.rows; ++r) {
    double z = 0;
    for (int k = 0; k < 10; ++k) z += truth[k] * b.col(k)[r];
    b.col(10)[r] = float(z);
  }
  TriangularSystem system;
  float alpha[kMaxChannels][kMaxFeatures];
  solve(b, system, alpha);
  for (int k = 0; k < 10; ++k) EXPECT_NEAR(alpha[0][k], truth[k], 2e-5f);
}

// A flat wall: constant normal (0, 0, 1) and constant w_z, so three feature columns are
// multiples of the constant one and T is rank-deficient.
Block flatWall(float noiseAmount, uint32_t seed) {
  const int side = 32, rows = side * side, features = 10;
  Block b{rows, features, 1, {}};
  b.allocate();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int r = 0; r < rows; ++r) {
    const float wx = float(r % side) / side * 2 - 1, wy = float(r / side) / side * 2 - 1, wz = 1.0f;
    const float f[10] = {1, 0, 0, 1, wx, wy, wz, wx * wx, wy * wy, wz * wz};
    for (int k = 0; k < features; ++k) b.col(k)[r] = f[k] + (k > 0 ? noiseAmount * u(rng) : 0.0f);
    b.col(features)[r] = 0.2f + 0.1f * wx + 0.05f * wy * wy;
  }
  return b;
}

TEST(BmfrQr, RankDeficientBlockIsFiniteWithRegularization) {
  TriangularSystem system;
  float alpha[kMaxChannels][kMaxFeatures];
  int deficient = 0;
  // Without noise the pivots of the constant columns vanish (the paper's NaN/Inf case; the
  // back substitution reports them instead of dividing by ~0).
  solve(flatWall(0.0f, 1), system, alpha, &deficient);
  EXPECT_GE(deficient, 1);
  // With eps = 0.01 every pivot is safely non-zero and the weights are finite.
  const Block clean = flatWall(0.0f, 2);
  solve(flatWall(0.01f, 2), system, alpha, &deficient);
  EXPECT_EQ(deficient, 0);
  double err = 0, norm = 0;
  for (int r = 0; r < clean.rows; ++r) {
    double y = 0;
    for (int k = 0; k < 10; ++k) {
      ASSERT_TRUE(std::isfinite(alpha[0][k]));
      y += double(alpha[0][k]) * clean.col(k)[r];  // synthesis with the noise-free T
    }
    err += (y - clean.col(10)[r]) * (y - clean.col(10)[r]);
    norm += double(clean.col(10)[r]) * clean.col(10)[r];
  }
  EXPECT_LT(std::sqrt(err / norm), 1e-2);
}

TEST(BmfrQr, FewerRowsThanFeaturesIsFinite) {
  Block b = randomBlock(6, 10, 3, 51);
  TriangularSystem system;
  float alpha[kMaxChannels][kMaxFeatures];
  int deficient = 0;
  solve(b, system, alpha, &deficient);
  EXPECT_EQ(deficient, 4);
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < 10; ++k) EXPECT_TRUE(std::isfinite(alpha[c][k]));
}

}  // namespace
}  // namespace rtd::bmfr
