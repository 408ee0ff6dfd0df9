// SPDX-License-Identifier: MIT
// Internal to graphslam (the optimizer's linearisation, the observability check): a fixed
// set of worker threads running one data-parallel loop at a time. The split of the work
// depends on the thread count, so callers make the result independent of it (each index
// writes only its own output; reductions run serially in index order).
#pragma once

#include <condition_variable>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace graphslam::support {

class ThreadPool {
 public:
  /// `threads` >= 1 counts the calling thread; threads - 1 workers are started.
  explicit ThreadPool(int threads);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  [[nodiscard]] int threads() const { return static_cast<int>(workers_.size()) + 1; }

  /// Calls fn(begin, end) on contiguous chunks covering [0, n), one per thread, and
  /// returns when all are done. Runs inline when n < min_chunk * 2 or with one thread.
  /// If chunks throw, the first exception (by chunk) is rethrown after all have finished.
  void parallelFor(std::size_t n, std::size_t min_chunk,
                   const std::function<void(std::size_t, std::size_t)>& fn);

 private:
  void work(int index);

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable start_, done_;
  const std::function<void(std::size_t, std::size_t)>* job_ = nullptr;
  std::size_t n_ = 0;
  int chunks_ = 0;
  std::size_t generation_ = 0;
  int pending_ = 0;
  std::vector<std::exception_ptr> errors_;  // per chunk
  bool stop_ = false;
};

}  // namespace graphslam::support
