// Wall-clock pass timing for FrameStats.
#pragma once
#include <chrono>
#include <string>

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

}  // namespace rtd
