#include "io/temp_files.h"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <string>

#include "rtd/error.h"
#include "rtd/sequence.h"

namespace rtd {

namespace fs = std::filesystem;

namespace {

// A fixed table, so that the signal handler reads it without locks or allocation: a slot is
// free (0), being filled (1) or holds a registered path (2). More writes in flight than slots
// are simply not registered (their temporary file is then left to removeStaleTemporaryFiles).
constexpr int kSlots = 64;
constexpr size_t kPathBytes = 4096;
struct Slot {
  std::atomic<int> state{0};
  char path[kPathBytes];
};
Slot slots[kSlots];

int registerPath(const std::string& p) {
  if (p.size() >= kPathBytes) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int expected = 0;
    if (slots[i].state.compare_exchange_strong(expected, 1)) {
      std::memcpy(slots[i].path, p.c_str(), p.size() + 1);
      slots[i].state.store(2);
      return i;
    }
  }
  return -1;
}

const char* const kTmp = ".tmp";

}  // namespace

TemporaryFile::TemporaryFile(const fs::path& final)
    : final_(final), path_(final.string() + kTmp + std::to_string(::getpid())) {
  slot_ = registerPath(path_.string());
}

TemporaryFile::~TemporaryFile() {
  if (!committed_) {
    std::error_code ec;
    fs::remove(path_, ec);
  }
  if (slot_ >= 0) slots[slot_].state.store(0);
}

void TemporaryFile::commit() {
  // Fault injection for the tests of interrupted runs: a signal arrives while the temporary
  // file exists and before it is renamed.
  if (const char* s = std::getenv("RTD_TEST_RAISE_BEFORE_RENAME")) ::raise(std::atoi(s));
  std::error_code ec;
  fs::rename(path_, final_, ec);
  if (ec) throw Error("cannot rename '" + path_.string() + "' to '" + final_.string() + "': " + ec.message());
  committed_ = true;
}

void removeTemporaryFiles() noexcept {
  for (Slot& s : slots)
    if (s.state.load() == 2) ::unlink(s.path);  // async-signal-safe
}

int removeStaleTemporaryFiles(const fs::path& dir) {
  int removed = 0;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    const size_t at = name.rfind(kTmp);
    if (at == std::string::npos || at + 4 == name.size()) continue;
    const std::string digits = name.substr(at + 4);
    if (digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) continue;
    const long pid = std::stol(digits);
    // Only files of processes that no longer exist: another run may be writing into the
    // same directory right now.
    if (pid == ::getpid() || pid <= 0 || !(::kill(pid_t(pid), 0) == -1 && errno == ESRCH)) continue;
    std::error_code rm;
    if (fs::remove(it->path(), rm)) ++removed;
  }
  return removed;
}

}  // namespace rtd
