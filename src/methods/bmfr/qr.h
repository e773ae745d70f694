// BMFR's least-squares core (Koskela et al. 2019 Sec. 4.2, Eqs. 4-7): Householder QR of the
// augmented block matrix [T + N, z_R, z_G, z_B] that keeps only R (Q is never formed), then
// back substitution R alpha = r per channel. A small self-contained unit so it can be tested
// against a double-precision reference and reused by other regression methods.
#pragma once
#include <cstddef>

namespace rtd::bmfr {

/// Most feature columns a block may have (1 + n + w + w^2 + material id + roughness).
constexpr int kMaxFeatures = 12;
/// Right-hand sides solved with one R (R, G, B).
constexpr int kMaxChannels = 3;

/// The triangular system left by the QR: R (features x features, upper triangular, row-major
/// in a kMaxFeatures stride) and r (the first `features` entries of each transformed channel).
struct TriangularSystem {
  int features = 0;
  int channels = 0;
  float R[kMaxFeatures][kMaxFeatures] = {};
  float r[kMaxChannels][kMaxFeatures] = {};
};

/// Column-major block: column c occupies cols[c * stride .. c * stride + rows). The first
/// `features` columns are T (+ N), the next `channels` columns are the right-hand sides.
/// Overwritten: the QR runs in place. stride >= rows rounded up to a multiple of 8 (the
/// padding rows are zeroed and take part as zeros).
///
/// Reflection k maps rows k.. of column k onto -sign(x_k) ||x|| e_k (the numerically stable
/// sign choice: u_k = x_k + sign(x_k) ||x|| never cancels), applied to every later column,
/// right-hand sides included, so r = (Q^T z)[0..features) without forming Q (Heath 1997
/// pp. 92-93). A column that is already zero below the diagonal, or whose remaining norm is
/// below 2^-20 of the largest pivot so far (rounding noise of a dependent column), is left alone
/// (R_kk = x_k, a rank deficiency for the back substitution to report).
void householderQr(float* cols, int rows, size_t stride, int features, int channels, TriangularSystem& out);

/// The same factorization for a matrix stored as row tiles, so each tile's reflections run in
/// L1 cache (a two-level "tall-skinny" Householder QR): tile t holds rows
/// [t * tileRows, min(rows, (t + 1) * tileRows)) with column c at
/// tiles[(t * (features + channels) + c) * tileStride]. Each tile is reduced to its
/// triangular [R_t | r_t]; the stacked triangles are reduced once more. R and r equal the
/// untiled ones up to the signs of their rows (R^T R = T^T T either way), so the solution is
/// the same. tileStride >= tileRows rounded up to 8. The tiles are overwritten.
void householderQrTiled(float* tiles, int rows, int tileRows, size_t tileStride, int features, int channels,
                        TriangularSystem& out);

/// Solves R alpha = r for every channel. A pivot |R_kk| <= relativePivotTolerance * max |R_jj|
/// counts as rank-deficient: its weight is set to 0 rather than dividing by (nearly) zero.
/// Returns the number of such pivots (0 for a full-rank system). alpha[c][k]: weight of
/// feature k for channel c.
int backSubstitute(const TriangularSystem& s, float alpha[kMaxChannels][kMaxFeatures],
                   float relativePivotTolerance = 1e-5f);

}  // namespace rtd::bmfr
