// SPDX-License-Identifier: MIT
// Test-only edge types that measure one direction of a point landmark from an SE(2) pose:
// a range and a bearing. A landmark seen only by them is the undetermined case of the
// observability check (range only, parallel bearings, one pose). The test plugin registers
// them for the tool's tests (tags TEST_RANGE_SE2_XY, TEST_BEARING_SE2_XY).
#pragma once

#include <cmath>

#include "graphslam/core/fixed_edge.h"
#include "graphslam/core/type_registry.h"
#include "graphslam/types_slam2d/se2.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"

namespace graphslam::test {

/// Range from pose x to point l: e = |l - t| - z. Numeric Jacobian.
class EdgeRangeSE2XY final
    : public BaseBinaryEdge<1, double, types_slam2d::VertexSE2, types_slam2d::VertexXY> {
 public:
  [[nodiscard]] ErrorVector evaluate(const types_slam2d::SE2& x,
                                     const Eigen::Vector2d& l) const override {
    ErrorVector e;
    e[0] = (l - x.translation()).norm() - measurement();
    return e;
  }
};

/// Bearing of point l in the frame of pose x: e = wrap(atan2(R^T (l - t)) - z). Numeric
/// Jacobian.
class EdgeBearingSE2XY final
    : public BaseBinaryEdge<1, double, types_slam2d::VertexSE2, types_slam2d::VertexXY> {
 public:
  [[nodiscard]] ErrorVector evaluate(const types_slam2d::SE2& x,
                                     const Eigen::Vector2d& l) const override {
    const Eigen::Vector2d d = x.rotation().transpose() * (l - x.translation());
    ErrorVector e;
    e[0] = types_slam2d::normalizeAngle(std::atan2(d.y(), d.x()) - measurement());
    return e;
  }
};

inline void registerRangeBearingEdges(TypeRegistry& types) {
  types.registerEdge<EdgeRangeSE2XY>("TEST_RANGE_SE2_XY");
  types.registerEdge<EdgeBearingSE2XY>("TEST_BEARING_SE2_XY");
}

}  // namespace graphslam::test
