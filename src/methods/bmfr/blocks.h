// BMFR's block grid (Koskela et al. 2019 Sec. 4.2): non-overlapping square blocks, displaced
// every frame by one of 16 static offsets, with mirrored pixels where a block leaves the image.
#pragma once
#include <algorithm>
#include <utility>
#include <vector>

namespace rtd::bmfr {

/// The authors' code's 16 grid offsets for 32x32 blocks (even values in [-16, 14]), used as
/// offset[frame % 16] in both axes; scaled by blockSize / 32 for other sizes.
inline constexpr int kBlockOffsets[16][2] = {{-14, -14}, {4, -6},   {-8, 14}, {8, 0},   {-10, -8}, {2, 12},
                                             {12, -12},  {-10, 0},  {12, 14}, {-8, -16}, {6, 6},    {-2, -2},
                                             {6, -14},   {-16, 12}, {14, -4}, {-6, 4}};

/// Pixel index i reflected into [0, n): -1 -> 0, -2 -> 1, n -> n - 1 (the code's mirroring,
/// which repeats the edge pixel). Clamped for blocks wider than the image.
inline int mirror(int i, int n) {
  if (i < 0) i = -i - 1;
  else if (i >= n) i = 2 * n - i - 1;
  return std::clamp(i, 0, n - 1);
}

/// Block (bx, by) covers pixels [originX + bx * size, originX + (bx + 1) * size) and the same
/// in y. The origin lies in [-size, -1], so ceil(extent / size) + 1 blocks per axis cover the
/// image; blocks that hold no image pixel are skipped.
struct BlockGrid {
  int size = 32;
  int originX = -16, originY = -16;
  int blocksX = 0, blocksY = 0;
  int width = 0, height = 0;

  int count() const { return blocksX * blocksY; }
  int blockX(int x) const { return (x - originX) / size; }  // x - originX > 0
  int blockY(int y) const { return (y - originY) / size; }
  int blockOf(int x, int y) const { return blockY(y) * blocksX + blockX(x); }
  int x0(int bx) const { return originX + bx * size; }
  int y0(int by) const { return originY + by * size; }
  /// Does block (bx, by) contain at least one image pixel?
  bool inImage(int bx, int by) const {
    return x0(bx) + size > 0 && x0(bx) < width && y0(by) + size > 0 && y0(by) < height;
  }
};

/// The grid of frame `frameIndex` (frames since the last reset); without offsets the grid
/// stays at the central offset (origin -size/2).
inline BlockGrid makeBlockGrid(int width, int height, int size, int frameIndex, bool offsets) {
  BlockGrid g;
  g.size = size;
  g.width = width;
  g.height = height;
  const int* o = kBlockOffsets[((frameIndex % 16) + 16) % 16];
  const int scale = size / 32 > 0 ? size / 32 : 1;
  g.originX = (offsets ? o[0] * scale : 0) - size / 2;
  g.originY = (offsets ? o[1] * scale : 0) - size / 2;
  g.blocksX = (width + size - 1) / size + 1;
  g.blocksY = (height + size - 1) / size + 1;
  return g;
}

/// A band of image rows [rowBegin, rowEnd) that holds whole block rows [blockRowBegin,
/// blockRowEnd): every row a block of the band reads, mirrored rows included, is in the band.
/// The CPU method runs phase I, the fit and phase III band by band, each band on one thread
/// while its rows are in cache.
struct RowBand {
  int rowBegin, rowEnd;
  int blockRowBegin, blockRowEnd;
};

/// The grid's block rows that hold image rows, one band each, except that a block row whose
/// mirrored rows lie in its neighbour's rows (a block row with fewer than half its rows inside
/// the image, at the top or bottom) shares its neighbour's band. Every image row is in exactly
/// one band.
inline std::vector<RowBand> rowBands(const BlockGrid& g) {
  std::vector<RowBand> bands;
  auto rows = [&](int by) { return std::pair{std::max(g.y0(by), 0), std::min(g.y0(by) + g.size, g.height)}; };
  // The lowest and highest image row block row `by` reads, mirrored rows included.
  auto reads = [&](int by) {
    int lo = g.height, hi = -1;
    for (int y = g.y0(by); y < g.y0(by) + g.size; ++y) {
      lo = std::min(lo, mirror(y, g.height));
      hi = std::max(hi, mirror(y, g.height));
    }
    return std::pair{lo, hi};
  };
  for (int by = 0; by < g.blocksY; ++by) {
    const auto [begin, end] = rows(by);
    if (begin >= end) continue;
    const int lo = reads(by).first;
    // Join the previous band if this block row reads rows above its own, or the previous
    // band's block rows read rows of this one.
    bool join = !bands.empty() && lo < begin;
    if (!bands.empty() && !join)
      for (int b = bands.back().blockRowBegin; b < bands.back().blockRowEnd; ++b) join = join || reads(b).second >= begin;
    if (join) {
      bands.back().rowEnd = end;
      bands.back().blockRowEnd = by + 1;
    } else {
      bands.push_back({begin, end, by, by + 1});
    }
  }
  return bands;
}

}  // namespace rtd::bmfr
