// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <type_traits>
#include <vector>

#include "graphslam/core/data_traits.h"
#include "graphslam/core/edge.h"
#include "graphslam/core/fixed_edge.h"

namespace graphslam {

/// Edge on any number of vertices of any types, chosen per instance with `setVertexIds()`
/// (g2o's BaseMultiEdge). The type overrides `computeError()` (writing `mutableError()`);
/// Jacobians are dynamic-size (`dimension() x vertex(i)->dimension()`), numeric by default
/// (vertices are perturbed in place, so linearisation of these edges is serial). Override
/// `linearizeOplus()` and fill `jacobian(i)` for analytic ones.
///
/// The error dimension is `D`, or, with `D = Eigen::Dynamic`, chosen per instance: such a
/// type overrides `resizeForVertices(n)` and calls `setErrorDimension()` there (g2o's
/// EDGE_SE2_LOTSOFXY: 2 per observed point). A measurement of type `Eigen::VectorXd` is
/// sized by the type as well; its flat data are its current size.
template <int D, typename MeasurementT>
class BaseMultiEdge : public Edge {
 public:
  static_assert(D > 0 || D == Eigen::Dynamic, "error dimension must be positive or Dynamic");
  static constexpr int kDimension = D;
  using Measurement = MeasurementT;
  using ErrorVector = Eigen::Matrix<double, D, 1>;
  using InformationMatrix = Eigen::Matrix<double, D, D>;
  using JacobianType = Eigen::Matrix<double, D, Eigen::Dynamic>;

  BaseMultiEdge() : Edge(D > 0 ? D : 0, -1) {
    error_.setZero(dimension());
    information_.setIdentity(dimension(), dimension());
  }

  [[nodiscard]] const Measurement& measurement() const { return measurement_; }
  void setMeasurement(const Measurement& m) { measurement_ = m; }
  [[nodiscard]] const InformationMatrix& information() const { return information_; }
  void setInformation(const InformationMatrix& info) { information_ = info; }
  [[nodiscard]] const ErrorVector& error() const { return error_; }

  /// Jacobian of slot i, sized dimension() x vertex(i)->dimension() on first use.
  [[nodiscard]] JacobianType& jacobian(std::size_t i) {
    ensureJacobians();
    return jacobians_[i];
  }
  [[nodiscard]] const JacobianType& jacobian(std::size_t i) const { return jacobians_.at(i); }

  void linearizeOplus() override {
    in_place_ = true;
    numericJacobians();
  }

  /// Central differences of the error for every non-fixed vertex (what linearizeOplus()
  /// does by default), perturbing the vertices in place.
  void numericJacobians() {
    ensureJacobians();
    const ErrorVector saved = error_;
    for (std::size_t i = 0; i < numVertices(); ++i) {
      if (vertex(i)->fixed()) {
        jacobians_[i].setZero();
      } else {
        numericJacobianInPlace(i, jacobians_[i].data());
      }
    }
    error_ = saved;
  }

  [[nodiscard]] double chi2() const override { return error_.dot(information_ * error_); }
  [[nodiscard]] bool perturbsVerticesInPlace() const override { return in_place_; }

  void constructQuadraticForm(const QuadraticFormTarget& t) const override {
    const int n = static_cast<int>(numVertices());
    const double weight = robustWeight();
    for (int a = 0; a < n; ++a) {
      if (t.b_offsets[a] < 0) continue;
      Eigen::MatrixXd JtW = jacobians_[a].transpose() * information_;
      if (weight != 1.0) JtW *= weight;
      Eigen::Map<Eigen::VectorXd>(t.gradient + t.b_offsets[a], JtW.rows()) += JtW * error_;
      for (int b = a; b < n; ++b) {
        const HessianBlockRef& ref = t.blocks[upperPairIndex(a, b, n)];
        if (ref.offset < 0) continue;
        const Eigen::MatrixXd block = JtW * jacobians_[b];
        if (!ref.transposed) {
          Eigen::Map<Eigen::MatrixXd, 0, Eigen::OuterStride<>>(
              t.hessian + ref.offset, block.rows(), block.cols(),
              Eigen::OuterStride<>(ref.stride)) += block;
        } else {
          Eigen::Map<Eigen::MatrixXd, 0, Eigen::OuterStride<>>(
              t.hessian + ref.offset, block.cols(), block.rows(),
              Eigen::OuterStride<>(ref.stride)) += block.transpose();
        }
      }
    }
  }

  [[nodiscard]] bool acceptsVertex(std::size_t /*slot*/, const Vertex& /*v*/) const override {
    return true;
  }
  [[nodiscard]] std::string expectedVertexType(std::size_t /*slot*/) const override {
    return "any vertex";
  }

  [[nodiscard]] const double* errorData() const override { return error_.data(); }
  [[nodiscard]] const double* jacobianData(std::size_t slot) const override {
    return jacobians_.at(slot).data();
  }

  [[nodiscard]] int measurementDataDimension() const override {
    if constexpr (kDynamicMeasurement) {
      return static_cast<int>(measurement_.size());
    } else {
      return DataTraits<Measurement>::kDimension;
    }
  }
  void getMeasurementData(double* data) const override {
    if constexpr (kDynamicMeasurement) {
      Eigen::Map<Eigen::VectorXd>(data, measurement_.size()) = measurement_;
    } else {
      DataTraits<Measurement>::toData(measurement_, data);
    }
  }
  void setMeasurementData(const double* data) override {
    if constexpr (kDynamicMeasurement) {
      measurement_ = Eigen::Map<const Eigen::VectorXd>(data, measurement_.size());
    } else {
      measurement_ = DataTraits<Measurement>::fromData(data);
    }
  }
  [[nodiscard]] const double* informationData() const override { return information_.data(); }
  void setInformationData(const double* data) override {
    information_ = Eigen::Map<const InformationMatrix>(data, dimension(), dimension());
  }

 protected:
  static constexpr bool kDynamicMeasurement = std::is_same_v<Measurement, Eigen::VectorXd>;

  ErrorVector& mutableError() { return error_; }
  Measurement& mutableMeasurement() { return measurement_; }

  /// With D = Eigen::Dynamic: sets the error dimension to `d` (only before the edge is in a
  /// graph); the error becomes zero, the information the identity.
  void setErrorDimension(int d) {
    static_assert(D == Eigen::Dynamic, "the error dimension of this type is fixed");
    setDimension(d);
    error_.setZero(d);
    information_.setIdentity(d, d);
    jacobians_.clear();
  }

 private:
  void ensureJacobians() {
    if (jacobians_.size() == numVertices()) return;
    jacobians_.resize(numVertices());
    for (std::size_t i = 0; i < numVertices(); ++i) {
      jacobians_[i] = JacobianType::Zero(dimension(), vertex(i) ? vertex(i)->dimension() : 0);
    }
  }

  Measurement measurement_{};
  InformationMatrix information_;
  ErrorVector error_;
  std::vector<JacobianType> jacobians_;
  bool in_place_ = false;  // the default numeric linearizeOplus() ran
};

}  // namespace graphslam
