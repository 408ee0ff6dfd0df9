// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <new>
#include <vector>

namespace graphslam::support {

/// Tuning of LargeArrayAllocator: which arrays get memory of their own on huge pages.
struct LargeArrayOptions {
  /// Arrays of at least this many bytes get a mapping of their own, aligned to 2 MiB,
  /// rounded up to a multiple of 2 MiB and advised for transparent huge pages. Below, the
  /// rounding would waste more than the page faults it saves.
  std::size_t huge_page_min_bytes = std::size_t{512} << 10;
  /// Arrays of more bytes stay on ordinary pages: fresh huge pages are slow to fault in on
  /// some (virtual) machines, and for arrays this large that outweighs the faults saved.
  std::size_t huge_page_max_bytes = std::size_t{8} << 20;
};

/// The options LargeArrayAllocator is built with. They are constants, not a setting: the
/// allocator is stateless, and an array's release must take the same path as its
/// allocation, so the bounds may not change while any array lives.
inline constexpr LargeArrayOptions kLargeArrayOptions{};

/// Which freed huge-page mappings are kept for reuse (setLargeArrayRetention).
struct LargeArrayRetention {
  /// At most this many freed mappings are kept ...
  std::size_t max_mappings = 8;
  /// ... holding at most this many bytes in all.
  std::size_t max_bytes = std::size_t{16} << 20;
};

/// The application's opt-in (Linux; elsewhere it does nothing): a freed huge-page array's
/// mapping is kept, within `retention`, for the next array of the same rounded length, so
/// that an optimisation following another (online SLAM re-optimising its graph, repeated
/// runs) finds its arrays' pages faulted in already instead of having the kernel zero
/// fresh ones. The kept mappings are the process's, shared by every thread, and stay
/// mapped until reused or until retention is turned off (LargeArrayRetention{0, 0}, which
/// releases them). By default nothing is kept: every array is unmapped when freed.
void setLargeArrayRetention(const LargeArrayRetention& retention);

namespace detail {
/// Memory of at least `bytes` (> 0) for a large array: on Linux, mapped on its own,
/// aligned to 2 MiB, rounded up to a multiple of 2 MiB and advised for transparent huge
/// pages (or a kept mapping of that length, setLargeArrayRetention); elsewhere from
/// operator new. Throws std::bad_alloc.
void* allocateLargeArray(std::size_t bytes);
/// Returns memory from allocateLargeArray() of the same `bytes`: unmapped, or kept when
/// the application asked for retention and there is room.
void deallocateLargeArray(void* p, std::size_t bytes) noexcept;
/// Bytes of freed mappings kept for reuse (0 off Linux and without retention).
std::size_t retainedLargeArrayBytes();
}  // namespace detail

/// Allocator of the large numeric arrays of the hot path (H's values and block
/// references, block-llt's factor and workspace). An array of
/// kLargeArrayOptions.huge_page_min_bytes to huge_page_max_bytes gets memory of its own,
/// aligned to 2 MiB and advised for transparent huge pages (Linux, when the kernel's
/// setting is "madvise" or "always"): the kernel then backs it with 2 MiB pages, and a
/// process touching it for the first time takes one page fault per 2 MiB instead of one
/// per 4 KiB. The rounding to 2 MiB costs at most 1.5 MiB of memory per array. Other sizes
/// come from operator new as usual.
template <class T>
class LargeArrayAllocator {
 public:
  using value_type = T;
  static constexpr std::size_t kHugePageMinBytes = kLargeArrayOptions.huge_page_min_bytes;
  static constexpr std::size_t kHugePageMaxBytes = kLargeArrayOptions.huge_page_max_bytes;

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

}  // namespace graphslam::support
