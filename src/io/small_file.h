// Reading a small untrusted file whole (sequence.json, cameras.json, TNND weights): only a
// regular file (a FIFO or /dev/zero would block or never end) of at most `maxBytes`.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>

namespace rtd {

/// The contents of `path`; rtd::Error starting with `what` (e.g. "TNND weights 'w.json'") when
/// it is missing, not a regular file, larger than `maxBytes` or unreadable.
std::string readSmallFile(const std::filesystem::path& path, std::uintmax_t maxBytes, const std::string& what);

}  // namespace rtd
