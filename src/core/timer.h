// Pass timing for FrameStats: wall clock and CPU time.
#pragma once
#include <atomic>
#include <chrono>
#include <ctime>
#include <string>
#include <vector>

#include "rtd/denoiser.h"

namespace rtd {

/// CPU time of the process (all threads) or of the calling thread, in nanoseconds.
inline int64_t cpuTimeNs(clockid_t clock = CLOCK_PROCESS_CPUTIME_ID) {
  timespec t{};
  clock_gettime(clock, &t);
  return int64_t(t.tv_sec) * 1000000000 + t.tv_nsec;
}

/// Measures one pass and appends it to stats when it goes out of scope.
class PassTimer {
 public:
  PassTimer(FrameStats& stats, std::string name)
      : stats_(stats), name_(std::move(name)), start_(std::chrono::steady_clock::now()), cpuStart_(cpuTimeNs()) {}
  ~PassTimer() {
    double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
    stats_.passes.push_back({std::move(name_), ms, double(cpuTimeNs() - cpuStart_) * 1e-6});
  }

 private:
  FrameStats& stats_;
  std::string name_;
  std::chrono::steady_clock::time_point start_;
  int64_t cpuStart_;
};

/// Times of passes that a method runs band by band on several threads (each band runs all of
/// them in turn): each band adds its durations, and report() appends each pass with its summed
/// thread time divided by the number of threads, its share of the wall time if the threads
/// were busy throughout; its CPU time is the bands' thread CPU time summed.
class BandPassTimes {
 public:
  explicit BandPassTimes(std::vector<std::string> names)
      : names_(std::move(names)), nanoseconds_(names_.size()), cpuNanoseconds_(names_.size()) {}

  /// Adds the time until it goes out of scope to pass k.
  class Scope {
   public:
    Scope(std::atomic<int64_t>& sum, std::atomic<int64_t>& cpuSum)
        : sum_(sum), cpuSum_(cpuSum), start_(std::chrono::steady_clock::now()), cpuStart_(cpuTimeNs(CLOCK_THREAD_CPUTIME_ID)) {}
    ~Scope() {
      sum_ += std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start_).count();
      cpuSum_ += cpuTimeNs(CLOCK_THREAD_CPUTIME_ID) - cpuStart_;
    }

   private:
    std::atomic<int64_t>&sum_, &cpuSum_;
    std::chrono::steady_clock::time_point start_;
    int64_t cpuStart_;
  };
  Scope scope(size_t k) { return Scope(nanoseconds_[k], cpuNanoseconds_[k]); }

  /// Passes that took no time (not run this frame) are left out.
  void report(FrameStats& stats, int threads) const {
    for (size_t k = 0; k < names_.size(); ++k)
      if (const int64_t ns = nanoseconds_[k].load(); ns > 0)
        stats.passes.push_back({names_[k], double(ns) * 1e-6 / threads, double(cpuNanoseconds_[k].load()) * 1e-6});
  }

 private:
  std::vector<std::string> names_;
  std::vector<std::atomic<int64_t>> nanoseconds_, cpuNanoseconds_;  // value-initialized: 0
};

}  // namespace rtd
