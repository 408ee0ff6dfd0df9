// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <new>
#include <vector>

namespace graphslam {

namespace detail {
/// Memory of at least `bytes` (> 0) for a large array: on Linux, mapped on its own,
/// aligned to 2 MiB, rounded up to a multiple of 2 MiB and advised for transparent huge
/// pages; elsewhere from operator new. Throws std::bad_alloc.
void* allocateLargeArray(std::size_t bytes);
/// Returns memory from allocateLargeArray() of the same `bytes`. On Linux the mapping is
/// kept for the next array of the same rounded length (at most 8 mappings, 16 MiB in
/// all), so that an optimisation following another finds its arrays' pages faulted in
/// already; beyond that it is unmapped.
void deallocateLargeArray(void* p, std::size_t bytes) noexcept;
/// Bytes of freed mappings kept for reuse (0 off Linux).
std::size_t retainedLargeArrayBytes();
}  // namespace detail

/// Allocator of the large numeric arrays of the hot path (H's values and block
/// references, block-llt's factor and workspace). An array of kHugePageMinBytes to
/// kHugePageMaxBytes gets memory of its own, aligned to 2 MiB and advised for transparent
/// huge pages (Linux, when the kernel's setting is "madvise" or "always"): the kernel then
/// backs it with 2 MiB pages, and a process touching it for the first time takes one page
/// fault per 2 MiB instead of one per 4 KiB. On the project's machines a 4 KiB fault costs
/// about 2.7 microseconds and a cold optimisation of citytrees10000 took about 2300 of
/// them; with these arrays on huge pages it takes about 1000 and reaches its target about
/// 2.5 ms (12 %) sooner. Larger arrays (the 100k- and 1M-pose graphs') stay on ordinary
/// pages: there huge pages made the optimisation 2-5 % slower (fresh huge pages are slow
/// to fault in on these virtual machines: 200 MB took 0.56 s against 0.14 s). Other sizes
/// come from operator new as usual. The rounding to 2 MiB costs at most 1.5 MiB of memory
/// per array. Freed, such an array's mapping is kept for the next one of the same rounded
/// length (deallocateLargeArray): a fresh 2 MiB page costs 0.24-0.52 ms of zeroing here,
/// and m3500b's H and factor take one each, every optimisation (0.5 ms of its 5.5 ms to
/// the target in repeated runs).
template <class T>
class LargeArrayAllocator {
 public:
  using value_type = T;
  static constexpr std::size_t kHugePageMinBytes = std::size_t{512} << 10;
  static constexpr std::size_t kHugePageMaxBytes = std::size_t{8} << 20;

  LargeArrayAllocator() noexcept = default;
  template <class U>
  LargeArrayAllocator(const LargeArrayAllocator<U>& /*other*/) noexcept {}  // NOLINT

  T* allocate(std::size_t n) {
    if (n > static_cast<std::size_t>(-1) / sizeof(T)) throw std::bad_array_new_length();
    const std::size_t bytes = n * sizeof(T);
    if (onHugePages(bytes)) return static_cast<T*>(detail::allocateLargeArray(bytes));
    return static_cast<T*>(::operator new (bytes, std::align_val_t{alignof(T)}));
  }
  void deallocate(T* p, std::size_t n) noexcept {
    const std::size_t bytes = n * sizeof(T);
    if (onHugePages(bytes)) {
      detail::deallocateLargeArray(p, bytes);
    } else {
      ::operator delete (p, std::align_val_t{alignof(T)});
    }
  }

  static constexpr bool onHugePages(std::size_t bytes) {
    return bytes >= kHugePageMinBytes && bytes <= kHugePageMaxBytes;
  }

  template <class U>
  bool operator==(const LargeArrayAllocator<U>& /*other*/) const noexcept {
    return true;
  }
  template <class U>
  bool operator!=(const LargeArrayAllocator<U>& /*other*/) const noexcept {
    return false;
  }
};

/// A std::vector whose memory comes from LargeArrayAllocator.
template <class T>
using LargeVector = std::vector<T, LargeArrayAllocator<T>>;

}  // namespace graphslam
