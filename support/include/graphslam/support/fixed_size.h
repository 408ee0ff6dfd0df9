// SPDX-License-Identifier: MIT
// Shared by the project's modules (installed with support's headers, not an API for
// programs): a run-time block size dispatched to a compile-time one, so that loops over a
// small block are unrolled.
#pragma once

#include <type_traits>

namespace graphslam::support {

/// f(std::integral_constant<int, D>{}) with D = d when d is one of Sizes, else with D = 0
/// (the callee reads d at run time). Every call of f must return the same type.
template <int First, int... Rest, typename F>
decltype(auto) withFixedSize(int d, F&& f) {
  if (d == First) return f(std::integral_constant<int, First>{});
  if constexpr (sizeof...(Rest) > 0) {
    return withFixedSize<Rest...>(d, f);
  } else {
    return f(std::integral_constant<int, 0>{});
  }
}

}  // namespace graphslam::support
