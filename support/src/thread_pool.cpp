// SPDX-License-Identifier: MIT
#include "graphslam/support/thread_pool.h"

#include <algorithm>

namespace graphslam::support {

ThreadPool::ThreadPool(int threads) {
  for (int i = 1; i < std::max(threads, 1); ++i) workers_.emplace_back([this, i] { work(i); });
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  start_.notify_all();
  for (auto& t : workers_) t.join();
}

namespace {
std::pair<std::size_t, std::size_t> chunk(std::size_t n, int chunks, int index) {
  const std::size_t per = n / static_cast<std::size_t>(chunks);
  const std::size_t rest = n % static_cast<std::size_t>(chunks);
  const auto i = static_cast<std::size_t>(index);
  const std::size_t begin = i * per + std::min(i, rest);
  return {begin, begin + per + (i < rest ? 1 : 0)};
}
}  // namespace

void ThreadPool::parallelFor(std::size_t n, std::size_t min_chunk,
                             const std::function<void(std::size_t, std::size_t)>& fn) {
  const std::size_t max_chunks = std::max<std::size_t>(n / std::max<std::size_t>(min_chunk, 1), 1);
  const int chunks = static_cast<int>(std::min<std::size_t>(max_chunks, threads()));
  if (chunks <= 1) {
    if (n > 0) fn(0, n);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    job_ = &fn;
    n_ = n;
    chunks_ = chunks;
    pending_ = chunks - 1;
    errors_.assign(static_cast<std::size_t>(chunks), nullptr);
    ++generation_;
  }
  start_.notify_all();
  const auto [begin, end] = chunk(n, chunks, 0);
  try {
    fn(begin, end);
  } catch (...) {
    errors_[0] = std::current_exception();  // the workers never touch slot 0
  }
  std::unique_lock<std::mutex> lock(mutex_);
  done_.wait(lock, [this] { return pending_ == 0; });
  job_ = nullptr;
  for (const auto& e : errors_) {
    if (e) std::rethrow_exception(e);
  }
}

void ThreadPool::work(int index) {
  std::size_t seen = 0;
  while (true) {
    std::unique_lock<std::mutex> lock(mutex_);
    start_.wait(lock, [&] { return stop_ || generation_ != seen; });
    if (stop_) return;
    seen = generation_;
    if (index >= chunks_) continue;  // fewer chunks than threads this time
    const auto* job = job_;
    const auto [begin, end] = chunk(n_, chunks_, index);
    lock.unlock();
    std::exception_ptr error;
    try {
      (*job)(begin, end);
    } catch (...) {
      error = std::current_exception();
    }
    lock.lock();
    errors_[static_cast<std::size_t>(index)] = error;
    if (--pending_ == 0) done_.notify_one();
  }
}

}  // namespace graphslam::support
