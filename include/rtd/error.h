// rtdenoise — the one exception type the library throws.
#pragma once
#include <stdexcept>
#include <string>

namespace rtd {

/// Every failure the library reports: bad input, a missing channel, an unknown setting,
/// an unavailable device. The message names the file, frame and channel where one applies.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace rtd
