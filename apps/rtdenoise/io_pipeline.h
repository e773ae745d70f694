// Overlapping a sequence's I/O with denoising (`rtdenoise denoise`, docs/cli.md "Denoised
// output"): ReadAhead reads the next frames on a thread of its own while the caller denoises
// the current one, WriteBehind writes the outputs, in order, on another. With depth 0 both do
// their work on the calling thread, when asked (--no-pipeline): the same calls in the same
// order, so the outputs are the same.
//
// Errors keep their meaning: an item that failed to read is reported by next() for that item,
// after every earlier item was handed out, and nothing after it is read; a job that failed
// stops every later job, and its exception is rethrown by the next submit() or finish().
#pragma once
#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>

namespace rtd::cli {

/// `denoise`'s depths: frame i + 1 is read while frame i is denoised; frame i - 1 is written
/// and frame i waits behind it (so a slow write delays denoising only when two are pending).
constexpr int kReadAheadFrames = 1;
constexpr int kWriteBehindFrames = 2;

/// Items 0 .. count-1 made by `read(i)`, in order, at most `depth` ready ahead of next().
template <class T>
class ReadAhead {
 public:
  ReadAhead(int count, int depth, std::function<T(int)> read) : count_(count), depth_(depth), read_(std::move(read)) {
    if (depth_ > 0) thread_ = std::thread([this] { run(); });
  }
  /// Stops reading: waits for the read in progress and drops what was not handed out.
  ~ReadAhead() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    changed_.notify_all();
    if (thread_.joinable()) thread_.join();
  }
  ReadAhead(const ReadAhead&) = delete;
  ReadAhead& operator=(const ReadAhead&) = delete;

  /// The next item (the first call: item 0); rethrows what reading it threw.
  T next() {
    if (depth_ == 0) return read_(taken_++);
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [this] { return !ready_.empty() || failure_; });
    if (ready_.empty()) std::rethrow_exception(failure_);
    T item = std::move(ready_.front());
    ready_.pop_front();
    lock.unlock();
    changed_.notify_all();
    return item;
  }

 private:
  void run() {
    for (int i = 0; i < count_; ++i) {
      {
        std::unique_lock lock(mutex_);
        changed_.wait(lock, [this] { return stop_ || int(ready_.size()) < depth_; });
        if (stop_) return;
      }
      std::optional<T> item;
      std::exception_ptr failure;
      try {
        item.emplace(read_(i));
      } catch (...) {
        failure = std::current_exception();
      }
      {
        std::lock_guard lock(mutex_);
        if (failure)
          failure_ = failure;
        else
          ready_.push_back(std::move(*item));
      }
      changed_.notify_all();
      if (failure) return;
    }
  }

  const int count_, depth_;
  const std::function<T(int)> read_;
  int taken_ = 0;  // depth 0
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<T> ready_;
  std::exception_ptr failure_;
  bool stop_ = false;
  std::thread thread_;
};

/// Jobs (writing one frame's outputs) run in the order submitted, at most `depth` queued or
/// running.
class WriteBehind {
 public:
  explicit WriteBehind(int depth) : depth_(depth) {
    if (depth_ > 0) thread_ = std::thread([this] { run(); });
  }
  /// Finishes the queued jobs (a failure among them is dropped: call finish() to see it).
  ~WriteBehind() {
    {
      std::lock_guard lock(mutex_);
      closing_ = true;
    }
    changed_.notify_all();
    if (thread_.joinable()) thread_.join();
  }
  WriteBehind(const WriteBehind&) = delete;
  WriteBehind& operator=(const WriteBehind&) = delete;

  /// Queues `job` (waits while `depth` jobs are queued or running; depth 0: runs it now).
  /// Rethrows the failure of an earlier job, and then does not queue this one.
  void submit(std::function<void()> job) {
    if (depth_ == 0) return job();
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [this] { return failure_ || int(queued_.size()) < depth_; });
    if (failure_) std::rethrow_exception(failure_);
    queued_.push_back(std::move(job));
    lock.unlock();
    changed_.notify_all();
  }
  /// Waits until every queued job ran; rethrows the first failure.
  void finish() {
    if (depth_ == 0) return;
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [this] { return failure_ || queued_.empty(); });
    if (failure_) std::rethrow_exception(failure_);
  }

 private:
  void run() {
    std::unique_lock lock(mutex_);
    for (;;) {
      changed_.wait(lock, [this] { return closing_ || !queued_.empty(); });
      if (queued_.empty() || failure_) return;  // closing, or stopped by a failure
      std::function<void()>& job = queued_.front();
      lock.unlock();
      std::exception_ptr failure;
      try {
        job();
      } catch (...) {
        failure = std::current_exception();
      }
      lock.lock();
      queued_.pop_front();  // popped only now: a queued job counts against depth while it runs
      if (failure) {
        failure_ = failure;
        queued_.clear();
      }
      changed_.notify_all();
    }
  }

  const int depth_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::function<void()>> queued_;
  std::exception_ptr failure_;
  bool closing_ = false;
  std::thread thread_;
};

}  // namespace rtd::cli
