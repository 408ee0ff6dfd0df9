// SPDX-License-Identifier: MIT
// Private to graphslam::core: wall-clock timing of the phases reported in summaries.
#pragma once

#include <chrono>

namespace graphslam::detail {

using Clock = std::chrono::steady_clock;

/// Seconds from a to b.
inline double seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

}  // namespace graphslam::detail
