// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <tuple>
#include <type_traits>
#include <typeinfo>
#include <utility>

#include "graphslam/core/data_traits.h"
#include "graphslam/core/edge.h"
#include "graphslam/support/error.h"

namespace graphslam {

namespace detail {

/// Calls f(std::integral_constant<int, 0>{}), ..., f(std::integral_constant<int, N-1>{}).
template <typename F, int... Is>
void staticForImpl(F&& f, std::integer_sequence<int, Is...>) {
  (f(std::integral_constant<int, Is>{}), ...);
}
template <int N, typename F>
void staticFor(F&& f) {
  staticForImpl(std::forward<F>(f), std::make_integer_sequence<int, N>{});
}

/// Thrown by the default FixedEdge::evaluate() so that the numeric Jacobian can fall back
/// to a type that overrides computeError() directly.
struct EvaluateNotProvided {};

}  // namespace detail

/// Edge of fixed error dimension `D`, measurement type `MeasurementT` and vertex types
/// `Vs...` (each a BaseVertex). The common base for new types.
///
/// A type implements one const `evaluate(estimates...)` returning the error; the base
/// then provides `computeError()`, a central-difference `linearizeOplus()` that works on
/// copies of the estimates (never mutating vertices), typed access (`vertex<I>()`,
/// `jacobian<I>()`), chi2, assembly into H and generic `.g2o` I/O of the measurement and
/// the upper triangle of the information matrix. Override `linearizeOplus()` to provide
/// analytic Jacobians (fill `jacobian<I>()` for every I).
///
/// A type written g2o-style, overriding `computeError()` and writing `error()` itself, is
/// supported too: its numeric Jacobian perturbs the vertices in place (serial only).
template <int D, typename MeasurementT, typename... Vs>
class FixedEdge : public Edge {
 public:
  static_assert(D > 0, "error dimension must be positive");
  static constexpr int kDimension = D;
  static constexpr int kArity = static_cast<int>(sizeof...(Vs));
  static_assert(kArity > 0, "an edge needs at least one vertex");

  using Measurement = MeasurementT;
  using ErrorVector = Eigen::Matrix<double, D, 1>;
  using InformationMatrix = Eigen::Matrix<double, D, D>;
  template <int I>
  using VertexXi = std::tuple_element_t<I, std::tuple<Vs...>>;
  template <int I>
  using JacobianXi = Eigen::Matrix<double, D, VertexXi<I>::kDimension>;
  using Estimates = std::tuple<typename Vs::EstimateType...>;

  FixedEdge() : Edge(D, kArity) {
    error_.setZero();
    information_.setIdentity();
    detail::staticFor<kArity>(
        [this](auto i) { std::get<decltype(i)::value>(jacobians_).setZero(); });
  }

  [[nodiscard]] const Measurement& measurement() const { return measurement_; }
  void setMeasurement(const Measurement& m) { measurement_ = m; }
  [[nodiscard]] const InformationMatrix& information() const { return information_; }
  void setInformation(const InformationMatrix& info) { information_ = info; }
  [[nodiscard]] const ErrorVector& error() const { return error_; }

  /// Typed access to the vertex in slot I.
  template <int I>
  [[nodiscard]] const VertexXi<I>& vertexXi() const {
    return static_cast<const VertexXi<I>&>(*vertex(I));
  }
  /// Jacobian of the error with respect to the tangent update of slot I.
  template <int I>
  [[nodiscard]] JacobianXi<I>& jacobian() {
    return std::get<I>(jacobians_);
  }
  template <int I>
  [[nodiscard]] const JacobianXi<I>& jacobian() const {
    return std::get<I>(jacobians_);
  }

  /// The error at the given estimates. Override this (preferred) or computeError().
  [[nodiscard]] virtual ErrorVector evaluate(const typename Vs::EstimateType&... /*x*/) const {
    throw detail::EvaluateNotProvided{};
  }

  /// Current estimates of all vertices, as copies.
  [[nodiscard]] Estimates estimates() const {
    return estimatesImpl(std::make_integer_sequence<int, kArity>{});
  }

  void computeError() override {
    try {
      error_ = evaluateAtCurrent(std::make_integer_sequence<int, kArity>{});
    } catch (const detail::EvaluateNotProvided&) {
      throw Error("edge type " + typeName(typeid(*this)) +
                  " overrides neither evaluate() nor computeError()");
    }
  }

  /// Numeric Jacobian by central differences (the default when a type gives no analytic
  /// one).
  void linearizeOplus() override { numericJacobians(); }

  /// Central differences of the error for every non-fixed vertex.
  void numericJacobians() {
    if (!g2o_style_) {
      try {
        numericJacobiansOnCopies();
        return;
      } catch (const detail::EvaluateNotProvided&) {
        g2o_style_ = true;
      }
    }
    numericJacobiansInPlace();
  }

  [[nodiscard]] double chi2() const override { return error_.dot(information_ * error_); }
  [[nodiscard]] bool perturbsVerticesInPlace() const override { return g2o_style_; }

  void constructQuadraticForm(const QuadraticFormTarget& t) const override {
    detail::staticFor<kArity>([&](auto ic) {
      constexpr int I = decltype(ic)::value;
      if (t.b_offsets[I] < 0) return;
      constexpr int DI = VertexXi<I>::kDimension;
      Eigen::Matrix<double, DI, D> JtW = jacobian<I>().transpose() * information_;
      if (robustKernel()) JtW *= robustWeight();
      Eigen::Map<Eigen::Matrix<double, DI, 1>>(t.gradient + t.b_offsets[I]) += JtW * error_;
      detail::staticFor<kArity>([&](auto jc) {
        constexpr int J = decltype(jc)::value;
        if constexpr (J >= I) {
          const HessianBlockRef& ref = t.blocks[upperPairIndex(I, J, kArity)];
          if (ref.offset < 0) return;
          constexpr int DJ = VertexXi<J>::kDimension;
          const Eigen::Matrix<double, DI, DJ> block = JtW * jacobian<J>();
          if (!ref.transposed) {
            Eigen::Map<Eigen::Matrix<double, DI, DJ>, 0, Eigen::OuterStride<>>(
                t.hessian + ref.offset, Eigen::OuterStride<>(ref.stride)) += block;
          } else {
            Eigen::Map<Eigen::Matrix<double, DJ, DI>, 0, Eigen::OuterStride<>>(
                t.hessian + ref.offset, Eigen::OuterStride<>(ref.stride)) += block.transpose();
          }
        }
      });
    });
  }

  [[nodiscard]] bool acceptsVertex(std::size_t slot, const Vertex& v) const override {
    bool ok = false;
    detail::staticFor<kArity>([&](auto ic) {
      constexpr int I = decltype(ic)::value;
      if (static_cast<std::size_t>(I) == slot) ok = dynamic_cast<const VertexXi<I>*>(&v) != nullptr;
    });
    return ok;
  }
  [[nodiscard]] std::string expectedVertexType(std::size_t slot) const override {
    std::string name;
    detail::staticFor<kArity>([&](auto ic) {
      constexpr int I = decltype(ic)::value;
      if (static_cast<std::size_t>(I) == slot) name = typeName(typeid(VertexXi<I>));
    });
    return name;
  }

  [[nodiscard]] const double* errorData() const override { return error_.data(); }
  [[nodiscard]] const double* jacobianData(std::size_t slot) const override {
    const double* p = nullptr;
    detail::staticFor<kArity>([&](auto ic) {
      constexpr int I = decltype(ic)::value;
      if (static_cast<std::size_t>(I) == slot) p = std::get<I>(jacobians_).data();
    });
    return p;
  }

  [[nodiscard]] int measurementDataDimension() const override {
    return DataTraits<Measurement>::kDimension;
  }
  void getMeasurementData(double* data) const override {
    DataTraits<Measurement>::toData(measurement_, data);
  }
  void setMeasurementData(const double* data) override {
    measurement_ = DataTraits<Measurement>::fromData(data);
  }
  [[nodiscard]] const double* informationData() const override { return information_.data(); }
  void setInformationData(const double* data) override {
    information_ = Eigen::Map<const InformationMatrix>(data);
  }

 protected:
  /// Writable error, for types that override computeError() directly (g2o style).
  ErrorVector& mutableError() { return error_; }

 private:
  /// evaluate() on the vertices' own estimates, without copying them (the hot path).
  template <int... Is>
  ErrorVector evaluateAtCurrent(std::integer_sequence<int, Is...>) const {
    return evaluate(vertexXi<Is>().estimate()...);
  }

  template <int... Is>
  Estimates estimatesImpl(std::integer_sequence<int, Is...>) const {
    return Estimates(vertexXi<Is>().estimate()...);
  }

  void numericJacobiansOnCopies() {
    const Estimates x0 = estimates();
    detail::staticFor<kArity>([&](auto ic) {
      constexpr int I = decltype(ic)::value;
      auto& J = std::get<I>(jacobians_);
      if (vertex(I)->fixed()) {
        J.setZero();
        return;
      }
      const VertexXi<I>& v = vertexXi<I>();
      typename VertexXi<I>::TangentVector delta;
      for (int k = 0; k < VertexXi<I>::kDimension; ++k) {
        Estimates xp = x0;
        Estimates xm = x0;
        delta.setZero();
        delta[k] = kNumericJacobianStep;
        std::get<I>(xp) = v.plus(std::get<I>(x0), delta);
        delta[k] = -kNumericJacobianStep;
        std::get<I>(xm) = v.plus(std::get<I>(x0), delta);
        const ErrorVector ep = std::apply([this](const auto&... x) { return evaluate(x...); }, xp);
        const ErrorVector em = std::apply([this](const auto&... x) { return evaluate(x...); }, xm);
        J.col(k) = (ep - em) / (2.0 * kNumericJacobianStep);
      }
    });
  }

  void numericJacobiansInPlace() {
    const ErrorVector saved = error_;
    detail::staticFor<kArity>([&](auto ic) {
      constexpr int I = decltype(ic)::value;
      auto& J = std::get<I>(jacobians_);
      if (vertex(I)->fixed()) {
        J.setZero();
      } else {
        numericJacobianInPlace(I, J.data());
      }
    });
    error_ = saved;
  }

  Measurement measurement_{};
  InformationMatrix information_;
  ErrorVector error_;
  std::tuple<Eigen::Matrix<double, D, Vs::kDimension>...> jacobians_;
  bool g2o_style_ = false;  // the type overrides computeError() instead of evaluate()
};

}  // namespace graphslam

namespace graphslam {

/// Edge on one vertex (a prior or an absolute measurement).
template <int D, typename MeasurementT, typename V0>
using BaseUnaryEdge = FixedEdge<D, MeasurementT, V0>;

/// Edge between two vertices (odometry, landmark observation).
template <int D, typename MeasurementT, typename V0, typename V1>
using BaseBinaryEdge = FixedEdge<D, MeasurementT, V0, V1>;

}  // namespace graphslam
