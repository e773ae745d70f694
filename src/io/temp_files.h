// Temporary files of atomic writes (writeFileAtomic, exr::writeChannels): each is registered
// while it exists, so that removeTemporaryFiles() (rtd/sequence.h) can delete them from a
// signal handler, and removeStaleTemporaryFiles() deletes those of killed processes.
#pragma once
#include <filesystem>

namespace rtd {

/// `<final>.tmp<pid>` registered from construction until destruction; the destructor removes
/// the file unless commit() renamed it to its final name.
class TemporaryFile {
 public:
  explicit TemporaryFile(const std::filesystem::path& final);
  ~TemporaryFile();
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;

  const std::filesystem::path& path() const { return path_; }
  /// Renames the file to its final name (rtd::Error naming both on failure).
  void commit();

 private:
  std::filesystem::path final_, path_;
  int slot_ = -1;
  bool committed_ = false;
};

}  // namespace rtd
