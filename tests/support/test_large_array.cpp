// SPDX-License-Identifier: MIT
// Large arrays: huge-page mappings, their retention and alignment.
#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "graphslam/support/large_array.h"

using namespace graphslam;

namespace {
/// Whether the mapping of this process that holds `p` carries the transparent huge page
/// advice ("hg" among its VmFlags in /proc/self/smaps); false when it is not found.
bool advisedForHugePages(const void* p) {
  std::ifstream smaps("/proc/self/smaps");
  const auto at = reinterpret_cast<std::uintptr_t>(p);
  std::string line;
  bool inside = false;
  while (std::getline(smaps, line)) {
    unsigned long long from = 0, to = 0;
    char dash = 0;
    std::istringstream head(line);
    if (head >> std::hex >> from >> dash >> to && dash == '-') {
      inside = at >= from && at < to;
    } else if (inside && line.rfind("VmFlags:", 0) == 0) {
      return (" " + line + " ").find(" hg ") != std::string::npos;
    }
  }
  return false;
}

struct alignas(32) Wide {
  double v[4];
};
}  // namespace

#if defined(__linux__)
// By default a freed huge-page array is unmapped: the library keeps nothing for itself.
TEST(Support_LargeArray, FreedMappingsAreNotKeptWithoutTheApplicationsOptIn) {
  const std::size_t n =
      support::LargeArrayAllocator<double>::kHugePageMinBytes / sizeof(double) + 10;
  { const support::LargeVector<double> a(n, 1.0); }
  EXPECT_EQ(support::detail::retainedLargeArrayBytes(), 0u);
}

// With the application's opt-in, a freed huge-page array's mapping serves the next array of
// the same rounded length (its pages are faulted in already); the mappings kept stay within
// their bound, and turning retention off releases them.
TEST(Support_LargeArray, FreedMappingsServeTheNextArrayOfTheSameRoundedLength) {
  const support::LargeArrayRetention retention;
  support::setLargeArrayRetention(retention);
  constexpr std::size_t kLarge = support::LargeArrayAllocator<double>::kHugePageMinBytes;
  const std::size_t n = kLarge / sizeof(double) + 10;  // rounded to 2 MiB
  const double* first = nullptr;
  {
    support::LargeVector<double> a(n, 1.0);
    first = a.data();
  }
  EXPECT_GE(support::detail::retainedLargeArrayBytes(), std::size_t{2} << 20);
  support::LargeVector<double> b(n + 1000, 2.0);  // the same rounded length
  EXPECT_EQ(b.data(), first);
  EXPECT_EQ(b.front(), 2.0);
  EXPECT_EQ(b.back(), 2.0);
  const support::LargeVector<double> c((std::size_t{3} << 20) / sizeof(double));  // 4 MiB rounded
  EXPECT_NE(c.data(), first);
  {
    std::vector<support::LargeVector<char>> many;
    for (int i = 0; i < 20; ++i) many.emplace_back(std::size_t{3} << 20);
  }
  EXPECT_LE(support::detail::retainedLargeArrayBytes(), retention.max_bytes);
  support::setLargeArrayRetention(support::LargeArrayRetention{0, 0});
  EXPECT_EQ(support::detail::retainedLargeArrayBytes(), 0u);
}
#endif

TEST(Support_LargeArray, SmallArraysAreOrdinaryLargeOnesAlignedAndAdvisedForHugePages) {
  constexpr std::size_t kLarge = support::LargeArrayAllocator<double>::kHugePageMinBytes;
  constexpr std::size_t kHuge = support::LargeArrayAllocator<double>::kHugePageMaxBytes;
  // Below the threshold: operator new with the element's alignment.
  support::LargeVector<Wide> small(10);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(small.data()) % alignof(Wide), 0u);
  // Growing across the threshold keeps the contents; the large array is zero-initialised
  // where resize() says so.
  support::LargeVector<double> v;
  for (std::size_t i = 0; i < kLarge / sizeof(double) + 1000; ++i) v.push_back(0.5 * i);
  for (std::size_t i = 0; i < v.size(); i += 997) ASSERT_EQ(v[i], 0.5 * i);
  v.resize(3 * kLarge / sizeof(double), 0.0);
  EXPECT_EQ(v.back(), 0.0);
  EXPECT_EQ(v[kLarge / sizeof(double)], 0.5 * (kLarge / sizeof(double)));
  const support::LargeVector<double> copy = v;
  EXPECT_TRUE(copy == v);
#if defined(__linux__)
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(v.data()) % (std::uintptr_t{2} << 20), 0u);
  std::ifstream thp("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string setting;
  std::getline(thp, setting);
  if (!setting.empty() && setting.find("[never]") == std::string::npos) {
    EXPECT_TRUE(advisedForHugePages(v.data())) << "THP setting: " << setting;
    EXPECT_FALSE(advisedForHugePages(small.data()));
    const support::LargeVector<char> beyond(kHuge + 1);
    EXPECT_FALSE(advisedForHugePages(beyond.data()));
  }
#endif
}
