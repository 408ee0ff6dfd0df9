// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/core/fixed_edge.h"
#include "graphslam/core/parameterized_edge.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/parameter_se2_offset.h"
#include "graphslam/types_slam2d/se2.h"
#include "graphslam/types_slam2d/vertex_se2.h"

namespace graphslam::types_slam2d {

/// Relative pose between two sensors, each mounted on a pose at an offset — `.g2o` tag
/// EDGE_SE2_OFFSET (g2o's layout: `EDGE_SE2_OFFSET i j offset_i offset_j dx dy dtheta`, then
/// the upper triangle of the 3x3 information; the two PARAMS_SE2OFFSET ids follow the vertex
/// ids). The measurement is the pose of sensor j in the frame of sensor i.
/// Error (g2o's convention): with the sensor poses A = X_i O_i and B = X_j O_j,
///   e = relativePoseError(Z, A, B) = t2v(Z^-1 (A^-1 B)).
/// Analytic Jacobians w.r.t. VertexSE2's update (g2o's type differentiates numerically).
class EdgeSE2Offset final : public ParameterizedEdge<BaseBinaryEdge<3, SE2, VertexSE2, VertexSE2>,
                                                     ParameterSE2Offset, ParameterSE2Offset> {
 public:
  [[nodiscard]] ErrorVector evaluate(const SE2& xi, const SE2& xj) const override {
    return relativePoseError(measurement(), xi * typedParameter<0>().offset(),
                             xj * typedParameter<1>().offset());
  }
  void linearizeOplus() override;
};

}  // namespace graphslam::types_slam2d
