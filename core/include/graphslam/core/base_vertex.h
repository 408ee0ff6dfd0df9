// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <type_traits>

#include "graphslam/core/data_traits.h"
#include "graphslam/core/vertex.h"

namespace graphslam {

/// Fixed-size vertex: tangent dimension `D`, estimate of type `EstimateT` (an Eigen vector
/// or any type with a `DataTraits` specialisation). A derived type implements only the
/// retraction `plus(x, delta)`; it must not mutate anything (it is applied to copies when
/// numeric Jacobians are formed).
template <int D, typename EstimateT>
class BaseVertex : public Vertex {
 public:
  static_assert(D > 0, "vertex dimension must be positive");
  static constexpr int kDimension = D;
  using EstimateType = EstimateT;
  using TangentVector = Eigen::Matrix<double, D, 1>;

  BaseVertex() : Vertex(D) {}

  [[nodiscard]] const EstimateType& estimate() const { return estimate_; }
  void setEstimate(const EstimateType& estimate) { estimate_ = estimate; }

  /// The manifold retraction x (+) delta. Pure function of its arguments.
  [[nodiscard]] virtual EstimateType plus(const EstimateType& x,
                                          const TangentVector& delta) const = 0;

  void oplus(const double* delta) final {
    estimate_ = plus(estimate_, Eigen::Map<const TangentVector>(delta));
  }
  /// The inverse of plus: writes delta with from (+) delta = x; false when the type does
  /// not define it (the default).
  [[nodiscard]] virtual bool minusEstimate(const EstimateType& /*x*/, const EstimateType& /*from*/,
                                           TangentVector& /*delta*/) const {
    return false;
  }
  [[nodiscard]] bool minus(const double* from, const double* step, double* delta) const final {
    TangentVector d;
    const EstimateType x =
        step ? plus(estimate_, Eigen::Map<const TangentVector>(step)) : estimate_;
    if (!minusEstimate(x, DataTraits<EstimateType>::fromData(from), d)) return false;
    Eigen::Map<TangentVector> out(delta);
    out = d;
    return true;
  }
  void push() final { backup_ = estimate_; }
  void pop() final { estimate_ = backup_; }

  [[nodiscard]] int estimateDataDimension() const override {
    return DataTraits<EstimateType>::kDimension;
  }
  void getEstimateData(double* data) const override {
    DataTraits<EstimateType>::toData(estimate_, data);
  }
  void setEstimateData(const double* data) override {
    estimate_ = DataTraits<EstimateType>::fromData(data);
  }

 private:
  /// The estimate of a new vertex: zero for Eigen vectors (whose default constructor leaves
  /// the coefficients uninitialised), the default-constructed value otherwise (the identity
  /// of a pose type).
  static EstimateType initialEstimate() {
    if constexpr (std::is_base_of_v<Eigen::DenseBase<EstimateType>, EstimateType>) {
      return EstimateType::Zero();
    } else {
      return EstimateType{};
    }
  }

  EstimateType estimate_ = initialEstimate();
  EstimateType backup_ = initialEstimate();
};

}  // namespace graphslam
