// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <cstddef>
#include <tuple>

#include "graphslam/core/edge.h"
#include "graphslam/core/parameter.h"

namespace graphslam {

/// Adds parameter slots of the types `Params...` to an edge base (a FixedEdge or
/// BaseMultiEdge instantiation):
///   class EdgeSE2Offset final
///       : public ParameterizedEdge<BaseBinaryEdge<3, SE2, VertexSE2, VertexSE2>,
///                                  ParameterSE2Offset, ParameterSE2Offset> { ... };
/// The graph resolves the ids when the edge is added and checks each parameter's type;
/// `typedParameter<I>()` then gives slot I's parameter as its type (valid in evaluate(),
/// computeError() and linearizeOplus()).
template <typename Base, typename... Params>
class ParameterizedEdge : public Base {
 public:
  static constexpr int kNumParameters = static_cast<int>(sizeof...(Params));
  static_assert(kNumParameters > 0, "ParameterizedEdge needs at least one parameter type");

  [[nodiscard]] int numParameters() const final { return kNumParameters; }
  [[nodiscard]] bool acceptsParameter(std::size_t slot, const Parameter& p) const final {
    using Check = bool (*)(const Parameter&);
    static constexpr std::array<Check, sizeof...(Params)> kChecks = {
        [](const Parameter& q) { return dynamic_cast<const Params*>(&q) != nullptr; }...};
    return slot < kChecks.size() && kChecks[slot](p);
  }

  /// The parameter of slot I (only once the edge is in a graph).
  template <int I>
  [[nodiscard]] const std::tuple_element_t<I, std::tuple<Params...>>& typedParameter() const {
    return static_cast<const std::tuple_element_t<I, std::tuple<Params...>>&>(*slots_[I].parameter);
  }

 protected:
  using typename Edge::ParameterSlot;
  [[nodiscard]] ParameterSlot* parameterSlots() final { return slots_.data(); }

 private:
  std::array<ParameterSlot, sizeof...(Params)> slots_{};
};

}  // namespace graphslam
