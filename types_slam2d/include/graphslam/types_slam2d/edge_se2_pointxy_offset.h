// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/core/fixed_edge.h"
#include "graphslam/core/parameterized_edge.h"
#include "graphslam/types_slam2d/parameter_se2_offset.h"
#include "graphslam/types_slam2d/se2.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"

namespace graphslam::types_slam2d {

/// Landmark l observed by a sensor mounted on pose X — `.g2o` tag EDGE_SE2_POINTXY_OFFSET
/// (g2o's layout: `EDGE_SE2_POINTXY_OFFSET pose point offset px py`, then the upper triangle
/// of the 2x2 information; the PARAMS_SE2OFFSET id follows the vertex ids).
/// Error, exactly g2o's: e = R^T (l - t) - z, the landmark in the frame of the *robot*: g2o's
/// type reads the offset and checks its type but leaves it out of the error (its simulator
/// makes the measurements the same way, so g2o's files are consistent with it). The
/// analytic Jacobians are those of this error (g2o's own multiply the heading column by the
/// offset's R^T, which agrees only for an offset without rotation).
class EdgeSE2PointXYOffset final
    : public ParameterizedEdge<BaseBinaryEdge<2, Eigen::Vector2d, VertexSE2, VertexXY>,
                               ParameterSE2Offset> {
 public:
  EdgeSE2PointXYOffset() { setMeasurement(Eigen::Vector2d::Zero()); }
  [[nodiscard]] ErrorVector evaluate(const SE2& x, const Eigen::Vector2d& l) const override {
    return x.inverseTimes(l) - measurement();
  }
  void linearizeOplus() override;
};

}  // namespace graphslam::types_slam2d
