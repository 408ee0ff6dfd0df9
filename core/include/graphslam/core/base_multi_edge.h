// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <vector>

#include "graphslam/core/data_traits.h"
#include "graphslam/core/edge.h"
#include "graphslam/core/fixed_edge.h"

namespace graphslam {

/// Edge of fixed error dimension `D` on any number of vertices of any types, chosen per
/// instance with `setVertexIds()` (g2o's BaseMultiEdge). The type overrides
/// `computeError()` (writing `mutableError()`); Jacobians are dynamic-size
/// (`D x vertex(i)->dimension()`), numeric by default (vertices are perturbed in place,
/// so linearisation of these edges is serial). Override `linearizeOplus()` and fill
/// `jacobian(i)` for analytic ones.
template <int D, typename MeasurementT>
class BaseMultiEdge : public Edge {
 public:
  static_assert(D > 0, "error dimension must be positive");
  static constexpr int kDimension = D;
  using Measurement = MeasurementT;
  using ErrorVector = Eigen::Matrix<double, D, 1>;
  using InformationMatrix = Eigen::Matrix<double, D, D>;
  using JacobianType = Eigen::Matrix<double, D, Eigen::Dynamic>;

  BaseMultiEdge() : Edge(D, -1) {
    error_.setZero();
    information_.setIdentity();
  }

  [[nodiscard]] const Measurement& measurement() const { return measurement_; }
  void setMeasurement(const Measurement& m) { measurement_ = m; }
  [[nodiscard]] const InformationMatrix& information() const { return information_; }
  void setInformation(const InformationMatrix& info) { information_ = info; }
  [[nodiscard]] const ErrorVector& error() const { return error_; }

  /// Jacobian of slot i, sized D x vertex(i)->dimension() on first use.
  [[nodiscard]] JacobianType& jacobian(std::size_t i) {
    ensureJacobians();
    return jacobians_[i];
  }
  [[nodiscard]] const JacobianType& jacobian(std::size_t i) const { return jacobians_.at(i); }

  void linearizeOplus() override {
    in_place_ = true;
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
  ErrorVector& mutableError() { return error_; }

 private:
  void ensureJacobians() {
    if (jacobians_.size() == numVertices()) return;
    jacobians_.resize(numVertices());
    for (std::size_t i = 0; i < numVertices(); ++i) {
      jacobians_[i] = JacobianType::Zero(D, vertex(i) ? vertex(i)->dimension() : 0);
    }
  }

  Measurement measurement_{};
  InformationMatrix information_;
  ErrorVector error_;
  std::vector<JacobianType> jacobians_;
  bool in_place_ = false;  // the default numeric linearizeOplus() ran
};

}  // namespace graphslam
