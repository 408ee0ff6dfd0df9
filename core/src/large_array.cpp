// SPDX-License-Identifier: MIT
#include "graphslam/core/large_array.h"

#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace graphslam::detail {

#if defined(__linux__)

namespace {
constexpr std::size_t kHugePage = std::size_t{2} << 20;
std::size_t roundUp(std::size_t bytes) { return (bytes + kHugePage - 1) / kHugePage * kHugePage; }
}  // namespace

void* allocateLargeArray(std::size_t bytes) {
  const std::size_t length = roundUp(bytes);
  if (length < bytes || length + kHugePage < length) throw std::bad_alloc();
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

void deallocateLargeArray(void* p, std::size_t bytes) noexcept {
  if (p) munmap(p, roundUp(bytes));
}

#else

// Aligned as a 64-byte cache line, enough for every element type of the hot path.
void* allocateLargeArray(std::size_t bytes) { return ::operator new (bytes, std::align_val_t{64}); }
void deallocateLargeArray(void* p, std::size_t /*bytes*/) noexcept {
  ::operator delete (p, std::align_val_t{64});
}

#endif

}  // namespace graphslam::detail
