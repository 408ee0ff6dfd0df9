// SPDX-License-Identifier: MIT
#include "graphslam/support/large_array.h"

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <mutex>
#include <utility>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace graphslam::support::detail {

#if defined(__linux__)

namespace {
constexpr std::size_t kHugePage = std::size_t{2} << 20;
std::size_t roundUp(std::size_t bytes) { return (bytes + kHugePage - 1) / kHugePage * kHugePage; }

/// Freed mappings kept for the next array of the same rounded length, within the limits
/// the application set (setLargeArrayRetention).
class Retained {
 public:
  /// New limits; mappings beyond them are unmapped (all of them for {0, 0}).
  void setLimits(const LargeArrayRetention& limits) {
    std::vector<std::pair<void*, std::size_t>> release;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      limits_ = limits;
      while (!kept_.empty() &&
             (kept_.size() > limits_.max_mappings || bytes_ > limits_.max_bytes)) {
        release.push_back(kept_.front());
        bytes_ -= kept_.front().second;
        kept_.erase(kept_.begin());
      }
    }
    for (const auto& m : release) munmap(m.first, m.second);
  }
  /// The most recently kept mapping of exactly `length` bytes, or nullptr.
  void* take(std::size_t length) {
    const std::lock_guard<std::mutex> lock(mutex_);
    const auto it = std::find_if(kept_.rbegin(), kept_.rend(),
                                 [length](const auto& m) { return m.second == length; });
    if (it == kept_.rend()) return nullptr;
    void* p = it->first;
    bytes_ -= length;
    kept_.erase(std::next(it).base());
    return p;
  }
  std::size_t bytes() {
    const std::lock_guard<std::mutex> lock(mutex_);
    return bytes_;
  }
  /// Keeps the mapping if there is room; false: the caller unmaps it.
  bool keep(void* p, std::size_t length) {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (kept_.size() >= limits_.max_mappings || bytes_ + length > limits_.max_bytes) return false;
    kept_.emplace_back(p, length);
    bytes_ += length;
    return true;
  }

 private:
  std::mutex mutex_;
  LargeArrayRetention limits_{0, 0};
  std::vector<std::pair<void*, std::size_t>> kept_;
  std::size_t bytes_ = 0;
};

/// Whether the application ever asked for retention: until then no list exists and
/// arrays are unmapped as they are freed.
std::atomic<bool> g_retention_requested{false};

/// Made at the application's first request; never destroyed, since arrays may be freed
/// during static destruction.
Retained& retained() {
  static Retained* r = new Retained;
  return *r;
}
}  // namespace

void* allocateLargeArray(std::size_t bytes) {
  const std::size_t length = roundUp(bytes);
  if (length < bytes || length + kHugePage < length) throw std::bad_alloc();
  if (g_retention_requested.load(std::memory_order_acquire)) {
    if (void* kept = retained().take(length)) return kept;
  }
  // One huge page more than needed, then the parts before and after the aligned range
  // are unmapped again.
  void* raw =
      mmap(nullptr, length + kHugePage, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (raw == MAP_FAILED) throw std::bad_alloc();
  const auto begin = reinterpret_cast<std::uintptr_t>(raw);
  const std::uintptr_t aligned = (begin + kHugePage - 1) / kHugePage * kHugePage;
  const std::size_t head = aligned - begin;
  const std::size_t tail = kHugePage - head;
  if (head > 0) munmap(raw, head);
  if (tail > 0) munmap(reinterpret_cast<void*>(aligned + length), tail);
  void* p = reinterpret_cast<void*>(aligned);
  // Advice only: without transparent huge pages (setting "never", older kernels) the
  // array gets ordinary pages.
  (void)madvise(p, length, MADV_HUGEPAGE);
  return p;
}

std::size_t retainedLargeArrayBytes() {
  return g_retention_requested.load(std::memory_order_acquire) ? retained().bytes() : 0;
}

void deallocateLargeArray(void* p, std::size_t bytes) noexcept {
  if (!p) return;
  bool kept = false;
  if (g_retention_requested.load(std::memory_order_acquire)) {
    try {
      kept = retained().keep(p, roundUp(bytes));
    } catch (...) {  // no room for the list's entry (or a lock failure): unmap
    }
  }
  if (!kept) munmap(p, roundUp(bytes));
}

void setRetention(const LargeArrayRetention& retention) {
  const bool none = retention.max_mappings == 0 || retention.max_bytes == 0;
  if (none && !g_retention_requested.load(std::memory_order_acquire)) return;  // nothing kept
  retained().setLimits(retention);
  g_retention_requested.store(true, std::memory_order_release);
}

#else

std::size_t retainedLargeArrayBytes() { return 0; }

// Aligned as a 64-byte cache line, enough for every element type of the hot path.
void* allocateLargeArray(std::size_t bytes) { return ::operator new (bytes, std::align_val_t{64}); }
void deallocateLargeArray(void* p, std::size_t /*bytes*/) noexcept {
  ::operator delete (p, std::align_val_t{64});
}

void setRetention(const LargeArrayRetention& /*retention*/) {}

#endif

}  // namespace graphslam::support::detail

void graphslam::support::setLargeArrayRetention(const LargeArrayRetention& retention) {
  detail::setRetention(retention);
}
