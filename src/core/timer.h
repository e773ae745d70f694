// Wall-clock pass timing for FrameStats.
#pragma once
#include <atomic>
#include <chrono>
#include <string>
#include <vector>

#include "rtd/denoiser.h"

namespace rtd {

/// Measures one pass and appends it to stats when it goes out of scope.
class PassTimer {
 public:
  PassTimer(FrameStats& stats, std::string name)
      : stats_(stats), name_(std::move(name)), start_(std::chrono::steady_clock::now()) {}
  ~PassTimer() {
    double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
    stats_.passes.push_back({std::move(name_), ms});
  }

 private:
  FrameStats& stats_;
  std::string name_;
  std::chrono::steady_clock::time_point start_;
};

/// Times of passes that a method runs band by band on several threads (each band runs all of
/// them in turn): each band adds its durations, and report() appends each pass with its summed
/// thread time divided by the number of threads, its share of the wall time if the threads
/// were busy throughout.
class BandPassTimes {
 public:
  explicit BandPassTimes(std::vector<std::string> names) : names_(std::move(names)), nanoseconds_(names_.size()) {}

  /// Adds the time until it goes out of scope to pass k.
  class Scope {
   public:
    Scope(std::atomic<int64_t>& sum) : sum_(sum), start_(std::chrono::steady_clock::now()) {}
    ~Scope() {
      sum_ += std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start_).count();
    }

   private:
    std::atomic<int64_t>& sum_;
    std::chrono::steady_clock::time_point start_;
  };
  Scope scope(size_t k) { return Scope(nanoseconds_[k]); }

  /// Passes that took no time (not run this frame) are left out.
  void report(FrameStats& stats, int threads) const {
    for (size_t k = 0; k < names_.size(); ++k)
      if (const int64_t ns = nanoseconds_[k].load(); ns > 0) stats.passes.push_back({names_[k], double(ns) * 1e-6 / threads});
  }

 private:
  std::vector<std::string> names_;
  std::vector<std::atomic<int64_t>> nanoseconds_;  // value-initialized: 0
};

}  // namespace rtd
