// Row-parallel loops on the device's oneTBB arena.
#pragma once
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace rtd {

/// Calls fn(y) for every row in [0, height), rows spread over the worker threads in chunks.
template <class Fn> void parallelRows(int height, Fn&& fn, int grain = 4) {
  tbb::parallel_for(tbb::blocked_range<int>(0, height, grain), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y != r.end(); ++y) fn(y);
  });
}

}  // namespace rtd
