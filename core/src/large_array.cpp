// SPDX-License-Identifier: MIT
#include "graphslam/core/large_array.h"

#include <algorithm>
#include <cstdint>
#include <mutex>
#include <utility>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace graphslam::detail {

#if defined(__linux__)

namespace {
constexpr std::size_t kHugePage = std::size_t{2} << 20;
std::size_t roundUp(std::size_t bytes) { return (bytes + kHugePage - 1) / kHugePage * kHugePage; }

/// Mappings freed recently, kept for the next array of the same rounded length: an
/// optimisation that follows another (online SLAM re-optimising its graph, repeated
/// benchmark runs) gets its H and factor without the kernel zeroing fresh huge pages
/// again (about 0.25 ms per 2 MiB here). At most kRetainedBytes in kRetainedMappings.
class Retained {
 public:
  static constexpr std::size_t kRetainedBytes = std::size_t{16} << 20;
  static constexpr std::size_t kRetainedMappings = 8;

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
    if (kept_.size() >= kRetainedMappings || bytes_ + length > kRetainedBytes) return false;
    kept_.emplace_back(p, length);
    bytes_ += length;
    return true;
  }

 private:
  std::mutex mutex_;
  std::vector<std::pair<void*, std::size_t>> kept_;
  std::size_t bytes_ = 0;
};

/// Never destroyed: arrays may be freed during static destruction.
Retained& retained() {
  static Retained* r = new Retained;
  return *r;
}
}  // namespace

void* allocateLargeArray(std::size_t bytes) {
  const std::size_t length = roundUp(bytes);
  if (length < bytes || length + kHugePage < length) throw std::bad_alloc();
  if (void* kept = retained().take(length)) return kept;
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

std::size_t retainedLargeArrayBytes() { return retained().bytes(); }

void deallocateLargeArray(void* p, std::size_t bytes) noexcept {
  if (!p) return;
  bool kept = false;
  try {
    kept = retained().keep(p, roundUp(bytes));
  } catch (...) {  // no room for the list's entry (or a lock failure): unmap
  }
  if (!kept) munmap(p, roundUp(bytes));
}

#else

std::size_t retainedLargeArrayBytes() { return 0; }

// Aligned as a 64-byte cache line, enough for every element type of the hot path.
void* allocateLargeArray(std::size_t bytes) { return ::operator new (bytes, std::align_val_t{64}); }
void deallocateLargeArray(void* p, std::size_t /*bytes*/) noexcept {
  ::operator delete (p, std::align_val_t{64});
}

#endif

}  // namespace graphslam::detail
