// SPDX-License-Identifier: MIT
// The SE(2) of the slam2d types: geometry's (exp/log, adjoint, Jacobians live there), and
// its `.g2o` numbers x y theta.
#pragma once

#include "graphslam/core/data_traits.h"
#include "graphslam/geometry/se2.h"

namespace graphslam::types_slam2d {
using geometry::normalizeAngle;
using geometry::rotation2;
using geometry::SE2;
}  // namespace graphslam::types_slam2d

namespace graphslam {
template <>
struct DataTraits<geometry::SE2> {
  static constexpr int kDimension = 3;
  static void toData(const geometry::SE2& v, double* out) {
    out[0] = v.translation().x();
    out[1] = v.translation().y();
    out[2] = v.angle();
  }
  static geometry::SE2 fromData(const double* in) { return geometry::SE2(in[0], in[1], in[2]); }
};
}  // namespace graphslam
