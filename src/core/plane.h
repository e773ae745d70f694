// A single float channel of an image: the CPU backend keeps every buffer as structure-of-arrays
// planes so inner loops over a row vectorize (see shared/notes/cpu-performance.md).
#pragma once
#include <array>
#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <new>
#ifdef __linux__
#include <sys/mman.h>
#endif
#include <cstddef>
#include <functional>
#include <string_view>
#include <vector>

namespace rtd {

/// Allocator for per-pixel arrays: each allocation starts on a 64-byte cache line, and
/// successive allocations start on different lines of a 4 KiB page. Planes of one image size
/// would otherwise all share their offset within a page (a 1280x720 float plane is exactly 900
/// pages), so element i of every plane maps to the same L1 cache set, and a pass that reads
/// more planes at once than the cache has ways (8) misses on every line: measured on the CI
/// machine, reprojection and accumulation (15-20 planes each) ran 2-3x slower that way.
/// Allocations of 1 MiB and more are mapped on 2 MiB boundaries with MADV_HUGEPAGE (Linux).
template <class T> struct StaggeredAllocator {
  using value_type = T;
  StaggeredAllocator() = default;
  template <class U> StaggeredAllocator(const StaggeredAllocator<U>&) noexcept {}

  T* allocate(size_t n) {
    static std::atomic<unsigned> next{0};
    constexpr size_t kLine = 64, kLines = 64;  // 64 lines: one 4 KiB page
    const size_t bytes = n * sizeof(T) + kLine * (kLines + 1);
    const size_t line = kLine * (next.fetch_add(1, std::memory_order_relaxed) % kLines);
    // Header before the data: the block to release and, for a mapping, its length.
    char* start;
    void* raw;
    size_t mapped = 0;
#ifdef __linux__
    if (bytes >= kHugeThreshold) {
      // Large planes on 2 MiB pages where the kernel allows it (THP "madvise" mode): a pass
      // streaming 15-45 rows of different planes at once otherwise runs out of L1 TLB entries.
      mapped = bytes + kHugePage;
      raw = mmap(nullptr, mapped, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
      if (raw == MAP_FAILED) throw std::bad_alloc();
      start = reinterpret_cast<char*>((reinterpret_cast<uintptr_t>(raw) + kHugePage - 1) & ~uintptr_t(kHugePage - 1));
      madvise(start, bytes, MADV_HUGEPAGE);
    } else
#endif
    {
      raw = std::malloc(bytes);
      if (!raw) throw std::bad_alloc();
      start = reinterpret_cast<char*>(raw);
    }
    const uintptr_t first = (reinterpret_cast<uintptr_t>(start) + 2 * sizeof(void*) + kLine - 1) & ~uintptr_t(kLine - 1);
    char* p = reinterpret_cast<char*>(first + line);
    reinterpret_cast<void**>(p)[-1] = raw;
    reinterpret_cast<size_t*>(p)[-2] = mapped;
    return reinterpret_cast<T*>(p);
  }
  void deallocate(T* p, size_t) noexcept {
    void* raw = reinterpret_cast<void**>(p)[-1];
    const size_t mapped = reinterpret_cast<size_t*>(p)[-2];
#ifdef __linux__
    if (mapped) {
      munmap(raw, mapped);
      return;
    }
#endif
    std::free(raw);
  }
  template <class U> bool operator==(const StaggeredAllocator<U>&) const noexcept { return true; }

 private:
  static constexpr size_t kHugePage = size_t(2) << 20, kHugeThreshold = size_t(1) << 20;
};

/// A per-pixel array (plane storage, reprojection taps).
template <class T> using PixelVector = std::vector<T, StaggeredAllocator<T>>;

struct Plane {
  int width = 0;
  int height = 0;
  PixelVector<float> data;

  Plane() = default;
  Plane(int w, int h, float fill = 0.0f) : width(w), height(h), data(size_t(w) * h, fill) {}

  void resize(int w, int h, float fill = 0.0f) {
    width = w;
    height = h;
    data.assign(size_t(w) * h, fill);
  }
  void fill(float v) { std::fill(data.begin(), data.end(), v); }
  bool empty() const { return data.empty(); }
  size_t size() const { return data.size(); }
  float* row(int y) { return data.data() + size_t(y) * width; }
  const float* row(int y) const { return data.data() + size_t(y) * width; }
  float& operator()(int x, int y) { return data[size_t(y) * width + x]; }
  float operator()(int x, int y) const { return data[size_t(y) * width + x]; }
  float* ptr() { return data.data(); }
  const float* ptr() const { return data.data(); }
};

/// Three planes: RGB radiance or an XYZ vector field.
using Plane3 = std::array<Plane, 3>;

inline void resize(Plane3& p, int w, int h, float fill = 0.0f) {
  for (auto& c : p) c.resize(w, h, fill);
}
/// Allocates p at w x h (zeros) where it is empty, for planes a pass allocates on first use
/// (released on a size change by assigning {}).
inline void allocateOnce(Plane3& p, int w, int h) {
  if (p[0].empty()) resize(p, w, h);
}

/// Receives every float array an object keeps (name, data, count): tests check invariants on
/// intermediate results with it (no subnormal anywhere, core/flush.h).
using PlaneVisitor = std::function<void(std::string_view name, const float* data, size_t count)>;

inline void visitPlane(const PlaneVisitor& visit, std::string_view name, const Plane& p) {
  if (!p.empty()) visit(name, p.ptr(), p.size());
}
inline void visitPlanes(const PlaneVisitor& visit, std::string_view name, const Plane3& p) {
  for (const Plane& c : p) visitPlane(visit, name, c);
}

/// Rec. 709 / sRGB-primaries luminance of linear RGB.
inline float luminance(float r, float g, float b) { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }

}  // namespace rtd
