// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/core/fixed_edge.h"
#include "graphslam/types_drivebot/vertex_vehicle.h"

namespace graphslam::types_drivebot {

/// Compass reading z = psi + offset + noise [rad] — `.g2o` tag EDGE_COMPASS, line
/// `EDGE_COMPASS id z offset wrap info(1)` (wrap is 1 or 0, see setWrapError).
/// Error: e = wrap(psi + offset - z). Analytic Jacobian [0, 0, 1].
class EdgeCompass final : public BaseUnaryEdge<1, double, VertexVehicle> {
 public:
  /// Angular offset of the compass from the platform heading [rad]; default 0.
  [[nodiscard]] double offset() const { return offset_; }
  void setOffset(double offset) { offset_ = offset; }

  /// Whether the error is wrapped to [-pi, pi) (default, correct). `false` reproduces the
  /// bug of the coursework's starter code (e = psi + offset - z, unwrapped): with an
  /// offset of 0.75 pi the readings wrap while the prediction does not, and the error
  /// jumps by 2 pi.
  [[nodiscard]] bool wrapError() const { return wrap_error_; }
  void setWrapError(bool wrap) { wrap_error_ = wrap; }

  [[nodiscard]] ErrorVector evaluate(const Eigen::Vector3d& x) const override {
    const double e = x[2] + offset_ - measurement();
    return ErrorVector(wrap_error_ ? wrapAngle(e) : e);
  }
  void linearizeOplus() override { jacobian<0>() << 0.0, 0.0, 1.0; }

  [[nodiscard]] int parameterDataDimension() const override { return 2; }
  void getParameterData(double* data) const override {
    data[0] = offset_;
    data[1] = wrap_error_ ? 1.0 : 0.0;
  }
  /// Throws graphslam::Error unless the wrap flag is 0 or 1.
  void setParameterData(const double* data) override;

 private:
  double offset_ = 0.0;
  bool wrap_error_ = true;
};

}  // namespace graphslam::types_drivebot
