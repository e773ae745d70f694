// Method "bmfr" (Koskela et al. 2019): phase I accumulates the demodulated 1-spp input with
// the shared reprojection, phase II fits every block of it as a least-squares combination of
// noise-free features (augmented Householder QR with stochastic regularization, qr.h), and
// phase III accumulates the fit again with phase I's taps and counts, remodulates, and applies
// TAA. docs/methods/bmfr.md describes every choice.
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "backend/cpu/cpu_denoiser.h"
#include "core/flush.h"
#include "core/parallel.h"
#include "methods/bmfr/blocks.h"
#include "methods/bmfr/bmfr_common.h"
#include "methods/bmfr/qr.h"
#include "passes/demodulation.h"
#include "passes/emitters.h"
#include "passes/reprojection.h"
#include "passes/taa.h"
#include "passes/taa_keys.h"
#include "passes/temporal_accumulation.h"
#include "rtd/methods/bmfr.h"
#include "core/simd.h"

// The whole CPU pipeline is compiled once per CPU path (core/simd.h); createBmfrCpu (bmfr.cpp)
// creates the current path's.
namespace rtd::RTD_SIMD_NS {

// This path's QR (qr_simd.cpp).
namespace bmfr {
void householderQrTiled(float* tiles, int rows, int tileRows, size_t tileStride, int features, int channels,
                        rtd::bmfr::TriangularSystem& out);
int backSubstitute(const rtd::bmfr::TriangularSystem& s, float alpha[rtd::bmfr::kMaxChannels][rtd::bmfr::kMaxFeatures],
                   float relativePivotTolerance);
}  // namespace bmfr

namespace {


using rtd::bmfr::kMaxChannels;
using rtd::bmfr::kMaxFeatures;

using rtd::bmfr::Feature;
using rtd::bmfr::FeatureKind;
using rtd::bmfr::hashUniform;

/// What phase II leaves per block for the synthesis: the weights and the normalization that
/// maps a raw feature f to (f - centre) * scale in [-1, 1].
struct BlockFit {
  float alpha[kMaxChannels][kMaxFeatures];
  float centre[kMaxFeatures];
  float scale[kMaxFeatures];
  float positionCentre[3];
};

/// Per-thread work space: one block's column-major [T | z_R z_G z_B] and pixel indices, and
/// one synthesized row.
struct Scratch {
  std::vector<float> columns;
  std::vector<int32_t> index;
  std::vector<float> rgb;
  std::vector<int32_t> emitterRows;  // the block's rows at emitter pixels (weighEmitterRows)
};

constexpr int kMaxBlock = 64;
constexpr size_t kMaxStride = size_t(kMaxBlock) * kMaxBlock;

// Eight-wide float vectors (GCC/Clang vector extensions: AVX where available, SSE pairs
// otherwise), for reductions the compiler will not vectorize on its own without -ffast-math.
typedef float Float8 __attribute__((vector_size(32), aligned(4)));

/// A feature's minimum and maximum over a block, kept per vector lane until read.
struct Range {
  Float8 lo = Float8{} + INFINITY, hi = Float8{} - INFINITY;
  void add(Float8 v) {
    lo = v < lo ? v : lo;
    hi = v > hi ? v : hi;
  }
  void add(float v) { add(Float8{} + v); }
  void add(const float* v, int n) {
    int i = 0;
    for (; i + 8 <= n; i += 8) add(*reinterpret_cast<const Float8*>(v + i));
    for (; i < n; ++i) add(v[i]);
  }
  float min() const {
    float m = lo[0];
    for (int k = 1; k < 8; ++k) m = std::min(m, lo[k]);
    return m;
  }
  float max() const {
    float m = hi[0];
    for (int k = 1; k < 8; ++k) m = std::max(m, hi[k]);
    return m;
  }
};

// The block's normalization of one feature: (f - centre) * scale spans [-1, 1] (Sec. 4.2:
// "T within every block is scaled to be in range [-1, 1]"). A feature that is constant on
// the block to rounding, its half range at most 1e-6 of `magnitude`, becomes a zero column,
// which the regularization noise fills. `magnitude` is the feature's own largest |f|, or for a
// channel of n or w the largest |f| of the vector's three channels on the block: a wall's
// z = -4 +- 1 ulp, or a floor's y = 0 +- rounding, is rounding noise of the position, not a
// feature (docs/methods/bmfr.md, "Constant features").
inline void normalization(const Range& range, float magnitude, float& centre, float& scale) {
  const float lo = range.min(), hi = range.max();
  centre = 0.5f * (lo + hi);
  const float half = 0.5f * (hi - lo);
  scale = half > rtd::bmfr::kConstantFeature * std::max(magnitude, 1e-30f) ? 1.0f / half : 0.0f;
}
inline float magnitudeOf(const Range& range) { return std::max(std::abs(range.min()), std::abs(range.max())); }

class BmfrCpu final : public CpuDenoiser<BmfrSettings> {
 public:
  using CpuDenoiser::CpuDenoiser;

  std::vector<Buffer> extraBuffers() const override { return rtd::bmfr::optionalBuffers(settings_); }
  std::vector<Buffer> requiredBuffers() const override { return rtd::bmfr::requiredBuffers(settings_); }

 protected:
  void resizeHistory(int w, int h) override {
    noisy_.resize(w, h, /*moments=*/false);  // BMFR reads no variance
    for (auto& f : filtered_) resize(f, w, h);
    resize(fitted_, w, h);
    resize(remodulated_, w, h);
    reprojection_.resize(w, h);
    taa_.resize(w, h);
    // The 32x32 grid has the most blocks; allocate for it whatever the current setting.
    const rtd::bmfr::BlockGrid g = rtd::bmfr::makeBlockGrid(w, h, 32, 0, true);
    fits_.assign(size_t(g.count()), BlockFit{});
    noise_.assign(size_t(kMaxFeatures) * kMaxStride, 0.0f);
  }

  void resetHistory() override {
    noisy_.reset();
    taa_.reset();
    frameIndex_ = 0;
  }
  void visitMethodPlanes(const PlaneVisitor& visit) const override {
    reprojection_.forEachPlane(visit);
    noisy_.forEachPlane(visit);
    for (const auto& f : filtered_) visitPlanes(visit, "phase III history", f);
    visitPlanes(visit, "fitted", fitted_);
    visitPlanes(visit, "remodulated", remodulated_);
    taa_.forEachPlane(visit);
    visit("block fits", reinterpret_cast<const float*>(fits_.data()), fits_.size() * sizeof(BlockFit) / sizeof(float));
    visit("noise", noise_.data(), noise_.size());
    visitPlane(visit, "emitter weights", emitterPlane_);
    for (const Scratch& s : scratch_) {
      visit("block columns", s.columns.data(), s.columns.size());
      visit("synthesized row", s.rgb.data(), s.rgb.size());
    }
  }

  const Plane3& process(const FrameData& frame, const FrameData* previous, Plane3& /*out*/, FrameStats& stats) override {
    const BmfrSettings& s = settings_;
    const auto* albedo = s.demodulate && frame.has(Buffer::Albedo) ? &frame.planes(Buffer::Albedo) : nullptr;
    const int prev = cur_;
    cur_ ^= 1;
    const int size = s.blockSize == BmfrBlockSize::Block64 ? 64 : 32;
    grid_ = rtd::bmfr::makeBlockGrid(frame.width, frame.height, size, frameIndex_, s.blockOffsets);
    Tiling tiling;
    // Issue 12: emitter pixels weigh 0 in the fits and keep their phase I value.
    emitterWeight_ = nullptr;
    if (s.fit && excludesEmitters(frame, s.emitters)) {
      PassTimer t(stats, "emitters");
      if (emitterWeights(frame, s.emitters, emitterPlane_) > 0) emitterWeight_ = &emitterPlane_;
    }
    if (s.fit) {
      selectFeatures(frame);
      tiling = makeTiling();
      if (s.noiseAmount > 0.0f) makeNoise(tiling.rows);
    }
    noisy_.advance();
    // Phase I: cumulative then exponential average, w = max(1/n, 0.2) (Sec. 4.1), with the
    // 8-bit-capped sample count, of the radiance demodulated on the fly; the accumulator's
    // luminance moments are not used.
    AccumulationOptions phaseOne;
    phaseOne.albedo = albedo;
    phaseOne.moments = false;
    // Phase III: the same taps and sample counts as phase I, w = max(1/n, 0.1) (Sec. 4.3).
    // Without phases II or III the image passes through.
    const Plane& length = noisy_.historyLength();
    const Plane3& filtered = s.accumulateFiltered ? filtered_[cur_] : s.fit ? fitted_ : noisy_.color();
    auto phaseThreeRow = [&](int y, Scratch& scratch) {
      const float* row[3] = {noisy_.color()[0].row(y), noisy_.color()[1].row(y), noisy_.color()[2].row(y)};
      if (s.fit) synthesizeRow(frame, y, scratch, row, noisy_.color());
      if (s.accumulateFiltered) accumulateRow(reprojection_, length, s.alphaFiltered, row, filtered_[prev], filtered_[cur_], y);
      else if (s.fit)
        for (int c = 0; c < 3; ++c) std::copy(row[c], row[c] + frame.width, fitted_[c].row(y));
      remodulateRow(filtered, albedo, remodulated_, y);
    };

    // Band by band (block rows, rtd::bmfr::rowBands), each on one thread: the reprojection and phase
    // I of a band's rows, the fit of its blocks and phase III run while the band is in cache;
    // the fit's reads of nine planes per block would otherwise come from memory.
    const std::vector<rtd::bmfr::RowBand> bands = rtd::bmfr::rowBands(grid_);
    BandPassTimes times({"reproject", "accumulateNoisy", "fit", s.fit ? "synthesize+accumulate+remodulate" : "accumulate+remodulate", "taa+export"});
    if (s.taa.taa) {
      // The own-surface box's keys (TaaSettings::taaOwnSurface): object id and the emitters
      // the fits leave out; computed before the bands, which read any row's neighbours.
      bool keyed = false;
      if (s.taa.taaOwnSurface) {
        PassTimer t(stats, "taa keys");
        keyed = taaSurfaceKeys(frame, &s.emitters, nullptr, taaKeys_);
      }
      taa_.begin(frame.width, frame.height, s.taa, keyed ? &taaKeys_ : nullptr, takeOutputRows());
    }
    tbb::parallel_for(tbb::blocked_range<size_t>(0, bands.size(), 1), [&](const tbb::blocked_range<size_t>& range) {
      Scratch& scratch = scratch_.local();
      for (size_t i = range.begin(); i != range.end(); ++i) {
        const rtd::bmfr::RowBand& band = bands[i];
        {
          auto t = times.scope(0);
          reprojectRows(frame, previous, s.reprojection, reprojection_, band.rowBegin, band.rowEnd);
        }
        {
          auto t = times.scope(1);
          noisy_.accumulateRows(reprojection_, frame.planes(Buffer::Color).data(), s.alphaNoisy, s.alphaNoisy,
                                s.maxHistoryLength, phaseOne, band.rowBegin, band.rowEnd);
        }
        if (s.fit) {
          auto t = times.scope(2);
          for (int by = band.blockRowBegin; by < band.blockRowEnd; ++by)
            for (int bx = 0; bx < grid_.blocksX; ++bx)
              if (grid_.inImage(bx, by))
                fitBlock(frame, noisy_.color(), bx, by, tiling, scratch, fits_[size_t(by * grid_.blocksX + bx)]);
        }
        {
          auto t = times.scope(3);
          for (int y = band.rowBegin; y < band.rowEnd; ++y) phaseThreeRow(y, scratch);
        }
        // TAA's 3x3 box needs the rows above and below: the band's first and last rows wait
        // for the neighbouring bands.
        if (s.taa.taa && band.rowEnd - band.rowBegin > 2) {
          auto t = times.scope(4);
          taa_.runRows(reprojection_, remodulated_, band.rowBegin + 1, band.rowEnd - 1);
        }
      }
    }, tbb::simple_partitioner());
    if (s.taa.taa) {
      parallelRows(int(bands.size()), [&](int i) {
        auto t = times.scope(4);
        const rtd::bmfr::RowBand& band = bands[size_t(i)];
        if (band.rowEnd - band.rowBegin > 2) {
          taa_.runRows(reprojection_, remodulated_, band.rowBegin, band.rowBegin + 1);
          taa_.runRows(reprojection_, remodulated_, band.rowEnd - 1, band.rowEnd);
        } else {
          taa_.runRows(reprojection_, remodulated_, band.rowBegin, band.rowEnd);
        }
      }, 1);
    }
    times.report(stats, tbb::this_task_arena::max_concurrency());
    ++frameIndex_;
    return s.taa.taa ? taa_.result() : remodulated_;
  }

 private:
  void selectFeatures(const FrameData& frame) {
    rtd::bmfr::selectFeatures(settings_, [&](Buffer b) { return frame.has(b); }, features_);
  }

  const Plane& rawPlane(const FrameData& frame, const Feature& f) const {
    switch (f.kind) {
      case FeatureKind::Normal: return frame.plane(Buffer::Normal, f.channel);
      case FeatureKind::Position:
      case FeatureKind::PositionSquared: return frame.plane(Buffer::Position, f.channel);
      case FeatureKind::MaterialId: return frame.plane(Buffer::MaterialId);
      default: return frame.plane(Buffer::Roughness);
    }
  }

  int rowsPerBlock() const {
    const int all = grid_.size * grid_.size;
    return settings_.samplesPerBlock > 0 ? std::min(settings_.samplesPerBlock, all) : all;
  }

  // The image pixel of each least-squares row of block (bx, by): every pixel of the block,
  // or `samplesPerBlock` jittered-stratified ones (per frame and block), mirrored at borders.
  void blockPixels(int bx, int by, int rows, int32_t* index) const {
    const int size = grid_.size, x0 = grid_.x0(bx), y0 = grid_.y0(by), w = grid_.width, h = grid_.height;
    if (rows == size * size) {
      for (int ly = 0; ly < size; ++ly) {
        const int y = rtd::bmfr::mirror(y0 + ly, h);
        for (int lx = 0; lx < size; ++lx) index[ly * size + lx] = y * w + rtd::bmfr::mirror(x0 + lx, w);
      }
      return;
    }
    int cellsX = 1;
    while (cellsX * cellsX < rows) ++cellsX;
    const int cellsY = (rows + cellsX - 1) / cellsX;
    const uint32_t block = uint32_t(by * grid_.blocksX + bx);
    for (int k = 0; k < rows; ++k) {
      const float jx = hashUniform(uint32_t(k), block, uint32_t(frameIndex_) * 2u);
      const float jy = hashUniform(uint32_t(k), block, uint32_t(frameIndex_) * 2u + 1u);
      const int lx = std::min(int((float(k % cellsX) + jx) * float(size) / float(cellsX)), size - 1);
      const int ly = std::min(int((float(k / cellsX) + jy) * float(size) / float(cellsY)), size - 1);
      index[k] = rtd::bmfr::mirror(y0 + ly, h) * w + rtd::bmfr::mirror(x0 + lx, w);
    }
  }

  // Uniform noise on [-eps, eps] per (row, feature), deterministic per frame and shared by
  // all blocks of the frame, as in the authors' code. Row r of feature k: noise_[k * kMaxStride + r].
  // The regularization's strength is the noise column's energy, rows * eps^2 / 3; the paper
  // tuned eps for 32x32 = 1024 rows, so fits with fewer rows (sub-sampled blocks) scale eps
  // by sqrt(1024 / rows) to keep that energy (docs/methods/bmfr.md).
  void makeNoise(int rows) {
    const float eps = settings_.noiseAmount * std::sqrt(std::max(1.0f, 1024.0f / float(rows)));
    const int m = int(features_.size());
    for (int k = 1; k < m; ++k)
      for (int r = 0; r < rows; ++r)
        noise_[size_t(k) * kMaxStride + r] = eps * (2.0f * hashUniform(uint32_t(r), uint32_t(k), uint32_t(frameIndex_)) - 1.0f);
  }

  // The block's rows in tiles of kTileRows (whole block rows), each tile's columns contiguous,
  // for rtd::bmfr::householderQrTiled: a tile of 512 rows x 13 columns (26 KiB) fits in a 32 KiB
  // L1. On the CI-class VM, 512-row tiles made the fit 10-12% faster than 256-row ones;
  // 128- and 1024-row tiles were slower.
  struct Tiling {
    int rows, tileRows, tileCount, columns;
    size_t tileStride;
    float* column(float* base, int t, int c) const { return base + (size_t(t) * columns + c) * tileStride; }
    int rowsIn(int t) const { return std::min(tileRows, rows - t * tileRows); }
  };
  static constexpr int kTileRows = 512;

  Tiling makeTiling() const {
    Tiling tiling;
    tiling.rows = rowsPerBlock();
    tiling.tileRows = std::min(tiling.rows, kTileRows);
    tiling.tileCount = (tiling.rows + tiling.tileRows - 1) / tiling.tileRows;
    tiling.columns = int(features_.size()) + 3;
    tiling.tileStride = (size_t(tiling.tileRows) + 15) & ~size_t(15);
    return tiling;
  }

  // Copies plane p over the block's rows into column c and returns the range of the values:
  // whole block rows at once where the block lies inside the image, through the block's
  // mirrored pixel columns `columnX` at the borders, through the sample indices when the
  // block is sub-sampled.
  Range gatherColumn(const Plane& p, int bx, int by, const Tiling& tiling, const int32_t* index, const int* columnX,
                     float* base, int c) const {
    const float* src = p.ptr();
    const int size = grid_.size;
    Range range;
    if (tiling.rows != size * size) {
      for (int r = 0; r < tiling.rows; ++r) {
        const float v = src[index[r]];
        tiling.column(base, r / tiling.tileRows, c)[r % tiling.tileRows] = v;
        range.add(v);
      }
      return range;
    }
    const int x0 = grid_.x0(bx), y0 = grid_.y0(by), w = grid_.width, h = grid_.height;
    const bool inside = x0 >= 0 && x0 + size <= w;
    for (int ly = 0; ly < size; ++ly) {
      const float* row = src + size_t(rtd::bmfr::mirror(y0 + ly, h)) * w;
      const int r0 = ly * size;  // a block row never straddles two tiles (kTileRows % size == 0)
      float* d = tiling.column(base, r0 / tiling.tileRows, c) + r0 % tiling.tileRows;
      if (inside) {  // size is 32 or 64: whole vectors
        for (int lx = 0; lx < size; lx += 8) {
          const Float8 v = *reinterpret_cast<const Float8*>(row + x0 + lx);
          *reinterpret_cast<Float8*>(d + lx) = v;
          range.add(v);
        }
      } else {
        for (int lx = 0; lx < size; ++lx) d[lx] = row[columnX[lx]];
        range.add(d, size);
      }
    }
    return range;
  }

  // Column k = (column `from` - centre)^2 (the same column when from == k); returns its range.
  Range squareColumn(float* base, const Tiling& tiling, int from, int k, float centre) const {
    Range range;
    for (int t = 0; t < tiling.tileCount; ++t) {
      const float* in = tiling.column(base, t, from);
      float* out = tiling.column(base, t, k);
      const int n = tiling.rowsIn(t);
      int r = 0;
      for (; r + 8 <= n; r += 8) {
        Float8 v = *reinterpret_cast<const Float8*>(in + r) - centre;
        v *= v;
        *reinterpret_cast<Float8*>(out + r) = v;
        range.add(v);
      }
      for (; r < n; ++r) {
        out[r] = (in[r] - centre) * (in[r] - centre);
        range.add(out[r]);
      }
    }
    return range;
  }

  // Widens `range` to cover plane p (or (p - centre)^2) over the block's image pixels.
  void extendOverBlock(const Plane& p, int bx, int by, float centre, bool squared, Range& range) const {
    const int x0 = std::max(grid_.x0(bx), 0), x1 = std::min(grid_.x0(bx) + grid_.size, grid_.width);
    const int y0 = std::max(grid_.y0(by), 0), y1 = std::min(grid_.y0(by) + grid_.size, grid_.height);
    float row[kMaxBlock];
    for (int y = y0; y < y1; ++y) {
      const float* src = p.row(y) + x0;
      const int n = x1 - x0;
      for (int i = 0; i < n; ++i) row[i] = squared ? (src[i] - centre) * (src[i] - centre) : src[i];
      range.add(row, n);
    }
  }

  // Issue 12: the rows of emitter pixels weigh 0 (every column of the row, the colour's
  // included, becomes 0), so the block's weights are those of its other pixels; the feature
  // ranges still cover the emitters (the synthesis does not use them there). A block whose
  // rows are all emitters keeps them: there is nothing else to fit (its other pixels, if it is
  // sub-sampled, would otherwise get weights 0).
  void weighEmitterRows(int by, const Tiling& tiling, const int32_t* index, const int* columnX, float* base,
                        Scratch& scratch) const {
    const int size = grid_.size, y0 = grid_.y0(by);
    const bool sampled = tiling.rows != size * size;
    const float* weight = emitterWeight_->ptr();
    std::vector<int32_t>& rows = scratch.emitterRows;
    rows.clear();
    for (int r = 0; r < tiling.rows; ++r) {
      const size_t i = sampled ? size_t(index[r])
                               : size_t(rtd::bmfr::mirror(y0 + r / size, grid_.height)) * grid_.width + size_t(columnX[r % size]);
      if (weight[i] == 0.0f) rows.push_back(r);
    }
    if (rows.size() == size_t(tiling.rows)) return;
    for (const int32_t r : rows)
      for (int c = 0; c < tiling.columns; ++c) tiling.column(base, r / tiling.tileRows, c)[r % tiling.tileRows] = 0.0f;
  }

  void fitBlock(const FrameData& frame, const Plane3& noisy, int bx, int by, const Tiling& tiling,
                Scratch& scratch, BlockFit& fit) const {
    if (scratch.columns.size() < size_t(kMaxFeatures + kMaxChannels) * kMaxStride) {
      scratch.columns.assign(size_t(kMaxFeatures + kMaxChannels) * kMaxStride, 0.0f);
      scratch.index.assign(kMaxStride, 0);
    }
    int32_t* index = scratch.index.data();
    float* base = scratch.columns.data();
    const int m = tiling.columns - 3;
    // Sub-sampled blocks take each feature's range over the samples and every image pixel
    // of the block, so the synthesis never meets a feature outside [-1, 1] (no extrapolation
    // beyond the normalized range; with all pixels as rows this holds by construction).
    const bool sampled = tiling.rows != grid_.size * grid_.size;
    if (sampled) blockPixels(bx, by, tiling.rows, index);
    int columnX[kMaxBlock];  // the block's pixel columns, mirrored at the image borders
    for (int lx = 0; lx < grid_.size; ++lx) columnX[lx] = rtd::bmfr::mirror(grid_.x0(bx) + lx, grid_.width);
    // Raw feature columns and their block range, all gathered before any is normalized, so
    // that the channels of n and w are judged against their vector's magnitude. The squares
    // are taken about the block's position mid-range (same span as w^2 with the constant and
    // w, better conditioned); w is gathered into the square's column if it is not a feature.
    int positionColumn[3] = {-1, -1, -1};
    Range ranges[kMaxFeatures], positionRange[3];
    // Gathers raw feature f into column k; its range covers every image pixel of a
    // sub-sampled block too.
    auto gatherFeature = [&](const Feature& f, int k) {
      Range range = gatherColumn(rawPlane(frame, f), bx, by, tiling, index, columnX, base, k);
      if (sampled) extendOverBlock(rawPlane(frame, f), bx, by, 0.0f, false, range);
      return range;
    };
    float normalMagnitude = 0.0f, positionMagnitude = 0.0f;
    for (int k = 0; k < m; ++k) {
      const Feature& f = features_[size_t(k)];
      if (f.kind == FeatureKind::Constant) {
        for (int t = 0; t < tiling.tileCount; ++t) std::fill_n(tiling.column(base, t, k), tiling.rowsIn(t), 1.0f);
        continue;
      }
      if (f.kind == FeatureKind::PositionSquared && positionColumn[f.channel] >= 0) continue;
      ranges[k] = gatherFeature(f, k);
      if (f.kind == FeatureKind::Position || f.kind == FeatureKind::PositionSquared) {
        positionColumn[f.channel] = k;
        positionRange[f.channel] = ranges[k];
        positionMagnitude = std::max(positionMagnitude, magnitudeOf(ranges[k]));
      } else if (f.kind == FeatureKind::Normal) {
        normalMagnitude = std::max(normalMagnitude, magnitudeOf(ranges[k]));
      }
    }
    for (int k = 0; k < m; ++k) {
      const Feature& f = features_[size_t(k)];
      switch (f.kind) {
        case FeatureKind::Constant:
          fit.centre[k] = 0.0f;
          fit.scale[k] = 1.0f;
          break;
        case FeatureKind::Normal: normalization(ranges[k], normalMagnitude, fit.centre[k], fit.scale[k]); break;
        case FeatureKind::Position: normalization(ranges[k], positionMagnitude, fit.centre[k], fit.scale[k]); break;
        case FeatureKind::PositionSquared: {
          const Range& w = positionRange[f.channel];
          const float pc = 0.5f * (w.min() + w.max());
          fit.positionCentre[f.channel] = pc;
          // A constant w has a constant square: (w - c)^2 of rounding noise spans [0, ulp^2]
          // and, judged against its own magnitude, would be normalized into a noise column.
          normalization(w, positionMagnitude, fit.centre[k], fit.scale[k]);
          if (fit.scale[k] == 0.0f) {
            fit.centre[k] = 0.0f;
            for (int t = 0; t < tiling.tileCount; ++t) std::fill_n(tiling.column(base, t, k), tiling.rowsIn(t), 0.0f);
            break;
          }
          Range range = squareColumn(base, tiling, positionColumn[f.channel], k, pc);
          if (sampled) extendOverBlock(rawPlane(frame, f), bx, by, pc, true, range);
          normalization(range, magnitudeOf(range), fit.centre[k], fit.scale[k]);
          break;
        }
        default: normalization(ranges[k], magnitudeOf(ranges[k]), fit.centre[k], fit.scale[k]);
      }
    }
    // Normalize to [-1, 1] and add the regularization noise to T only (Eq. 7); the synthesis
    // uses the noise-free T.
    const bool regularize = settings_.noiseAmount > 0.0f;
    for (int k = 1; k < m; ++k)
      for (int t = 0; t < tiling.tileCount; ++t) {
        float* col = tiling.column(base, t, k);
        const float* n = noise_.data() + size_t(k) * kMaxStride + size_t(t) * tiling.tileRows;
        const float centre = fit.centre[k], scale = fit.scale[k];
        const int rows = tiling.rowsIn(t);
        if (regularize)
          for (int r = 0; r < rows; ++r) col[r] = (col[r] - centre) * scale + n[r];
        else
          for (int r = 0; r < rows; ++r) col[r] = (col[r] - centre) * scale;
      }
    for (int c = 0; c < 3; ++c) gatherColumn(noisy[c], bx, by, tiling, index, columnX, base, m + c);
    if (emitterWeight_) weighEmitterRows(by, tiling, index, columnX, base, scratch);

    rtd::bmfr::TriangularSystem system;
    bmfr::householderQrTiled(base, tiling.rows, tiling.tileRows, tiling.tileStride, m, 3, system);
    bmfr::backSubstitute(system, fit.alpha, 1e-5f);
  }

  // Eq. 6: y = T alpha per pixel of row y with its block's weights and normalization,
  // clamped >= 0, into the scratch row; `out` then points at it. Each feature is clamped to
  // the fitted range [-1, 1]: a no-op up to rounding, since the block's normalization covers
  // all of its pixels.
  // Emitter pixels (issue 12) take their own value from `noisy` (phase I) instead.
  void synthesizeRow(const FrameData& frame, int y, Scratch& scratch, const float* out[3], const Plane3& noisy) const {
    const int w = frame.width, m = int(features_.size());
    if (scratch.rgb.size() < size_t(3 * w)) scratch.rgb.assign(size_t(3 * w), 0.0f);
    float* outRow[3] = {scratch.rgb.data(), scratch.rgb.data() + w, scratch.rgb.data() + 2 * w};
    const float* src[kMaxFeatures];
    for (int k = 1; k < m; ++k) src[k] = rawPlane(frame, features_[size_t(k)]).row(y);
    const int by = grid_.blockY(y);
    for (int x0 = 0; x0 < w;) {
      const int bx = grid_.blockX(x0);
      const int x1 = std::min(w, grid_.x0(bx) + grid_.size);
      const BlockFit& fit = fits_[size_t(by * grid_.blocksX + bx)];
      // The normalized feature k of pixel x.
      auto feature = [&](int k, int x) {
        const auto f = features_[size_t(k)].kind == FeatureKind::PositionSquared
                           ? (src[k][x] - fit.positionCentre[features_[size_t(k)].channel]) * (src[k][x] - fit.positionCentre[features_[size_t(k)].channel])
                           : src[k][x];
        return (f - fit.centre[k]) * fit.scale[k];
      };
      int x = x0;
      // Eight pixels at a time, the three channels' sums in registers.
      for (; x + 8 <= x1; x += 8) {
        Float8 sum[3];
        for (int c = 0; c < 3; ++c) sum[c] = Float8{} + fit.alpha[c][0];
        for (int k = 1; k < m; ++k) {
          Float8 v = *reinterpret_cast<const Float8*>(src[k] + x);
          if (features_[size_t(k)].kind == FeatureKind::PositionSquared) {
            v -= fit.positionCentre[features_[size_t(k)].channel];
            v *= v;
          }
          v = (v - fit.centre[k]) * fit.scale[k];
          v = v < -1.0f ? Float8{} - 1.0f : v;
          v = v > 1.0f ? Float8{} + 1.0f : v;
          for (int c = 0; c < 3; ++c) sum[c] += fit.alpha[c][k] * v;
        }
        // Clamped at 0; below kTiny also 0 (core/flush.h).
        for (int c = 0; c < 3; ++c) *reinterpret_cast<Float8*>(outRow[c] + x) = sum[c] >= kTiny ? sum[c] : Float8{};
      }
      for (; x < x1; ++x) {
        float sum[3] = {fit.alpha[0][0], fit.alpha[1][0], fit.alpha[2][0]};
        for (int k = 1; k < m; ++k) {
          const float v = std::clamp(feature(k, x), -1.0f, 1.0f);
          for (int c = 0; c < 3; ++c) sum[c] += fit.alpha[c][k] * v;
        }
        for (int c = 0; c < 3; ++c) outRow[c][x] = sum[c] >= kTiny ? sum[c] : 0.0f;
      }
      x0 = x1;
    }
    if (emitterWeight_) {
      const float* weight = emitterWeight_->row(y);
      for (int x = 0; x < w; ++x)
        if (weight[x] == 0.0f)
          for (int c = 0; c < 3; ++c) outRow[c][x] = noisy[c].row(y)[x];
    }
    for (int c = 0; c < 3; ++c) out[c] = outRow[c];
  }


  Plane3 fitted_, remodulated_;
  TemporalAccumulator noisy_;  // phase I history: accumulated colour and sample count
  Plane3 filtered_[2];         // phase III history
  int cur_ = 0;
  int frameIndex_ = 0;
  Reprojection reprojection_;
  Taa taa_;
  PixelVector<uint32_t> taaKeys_;  // TaaSettings::taaOwnSurface
  rtd::bmfr::BlockGrid grid_;
  std::vector<Feature> features_;
  std::vector<BlockFit> fits_;
  std::vector<float> noise_;
  Plane emitterPlane_;                   // 0 at emitter pixels, 1 elsewhere (issue 12)
  const Plane* emitterWeight_ = nullptr;  // &emitterPlane_ on frames with emitters to exclude, else null
  tbb::enumerable_thread_specific<Scratch> scratch_;
};

}  // namespace

std::unique_ptr<Denoiser> createBmfrCpu(tbb::task_arena& arena) { return std::make_unique<BmfrCpu>(arena); }

}  // namespace rtd::RTD_SIMD_NS
