// BMFR's block grid (Koskela et al. 2019 Sec. 4.2): non-overlapping square blocks, displaced
// every frame by one of 16 static offsets, with mirrored pixels where a block leaves the image.
#pragma once
#include <algorithm>

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

}  // namespace rtd::bmfr
