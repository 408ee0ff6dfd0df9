// SPDX-License-Identifier: MIT
// g2o's 3D edges. Errors follow g2o's conventions exactly: a pose error is
// (translation, vector part of the unit quaternion with non-negative scalar part) of the
// error transform, and the information matrix is ordered the same way.
#pragma once

#include "graphslam/core/fixed_edge.h"
#include "graphslam/core/parameterized_edge.h"
#include "graphslam/types_slam3d/parameter_se3_offset.h"
#include "graphslam/types_slam3d/vertex_se3.h"

namespace graphslam::types_slam3d {

/// Relative pose z = X_i^-1 X_j — `.g2o` tag EDGE_SE3:QUAT (i j, x y z qx qy qz qw, the
/// upper triangle of the 6x6 information).
/// Error: compact(Z^-1 X_i^-1 X_j).
class EdgeSE3 final : public BaseBinaryEdge<6, SE3, VertexSE3, VertexSE3> {
 public:
  [[nodiscard]] ErrorVector evaluate(const SE3& xi, const SE3& xj) const override {
    return (measurement().inverse() * (xi.inverse() * xj)).toCompactVector();
  }
  void linearizeOplus() override;
};

/// Relative pose between two sensors on two poses — `.g2o` tag EDGE_SE3_OFFSET
/// (i j offset_i offset_j, x y z qx qy qz qw, information 21).
/// Error: compact(Z^-1 (X_i P_i)^-1 (X_j P_j)).
class EdgeSE3Offset final : public ParameterizedEdge<BaseBinaryEdge<6, SE3, VertexSE3, VertexSE3>,
                                                     ParameterSE3Offset, ParameterSE3Offset> {
 public:
  [[nodiscard]] ErrorVector evaluate(const SE3& xi, const SE3& xj) const override {
    const SE3& pi = typedParameter<0>().offset();
    const SE3& pj = typedParameter<1>().offset();
    return (measurement().inverse() * (xi * pi).inverse() * (xj * pj)).toCompactVector();
  }
  void linearizeOplus() override;
};

/// Absolute pose of a sensor — `.g2o` tag EDGE_SE3_PRIOR (i offset, x y z qx qy qz qw,
/// information 21). Error: compact(Z^-1 X P).
class EdgeSE3Prior final
    : public ParameterizedEdge<BaseUnaryEdge<6, SE3, VertexSE3>, ParameterSE3Offset> {
 public:
  [[nodiscard]] ErrorVector evaluate(const SE3& x) const override {
    return (measurement().inverse() * (x * typedParameter<0>().offset())).toCompactVector();
  }
  void linearizeOplus() override;
};

/// Absolute position of a pose — `.g2o` tag EDGE_SE3_XYZ_PRIOR (i offset, x y z,
/// information 6). Error: t - z. The line names an offset parameter, which g2o's error
/// does not use either (kept for the file layout).
class EdgeSE3XYZPrior final
    : public ParameterizedEdge<BaseUnaryEdge<3, Eigen::Vector3d, VertexSE3>, ParameterSE3Offset> {
 public:
  [[nodiscard]] ErrorVector evaluate(const SE3& x) const override {
    return x.translation() - measurement();
  }
  void linearizeOplus() override;
};

/// A point seen from a sensor on a pose — `.g2o` tag EDGE_SE3_TRACKXYZ (pose point offset,
/// x y z, information 6). Error: (X P)^-1 p - z.
class EdgeSE3PointXYZ final
    : public ParameterizedEdge<BaseBinaryEdge<3, Eigen::Vector3d, VertexSE3, VertexPointXYZ>,
                               ParameterSE3Offset> {
 public:
  [[nodiscard]] ErrorVector evaluate(const SE3& x, const Eigen::Vector3d& p) const override {
    return typedParameter<0>().inverseOffset() * (x.inverse() * p) - measurement();
  }
  void linearizeOplus() override;
};

/// Displacement between two points — `.g2o` tag EDGE_POINTXYZ (i j, x y z, information 6).
/// Error: (p_j - p_i) - z.
class EdgePointXYZ final
    : public BaseBinaryEdge<3, Eigen::Vector3d, VertexPointXYZ, VertexPointXYZ> {
 public:
  [[nodiscard]] ErrorVector evaluate(const Eigen::Vector3d& pi,
                                     const Eigen::Vector3d& pj) const override {
    return (pj - pi) - measurement();
  }
  void linearizeOplus() override;
};

/// Absolute position of a point — `.g2o` tag EDGE_POINTXYZ_PRIOR (i, x y z,
/// information 6). Error: p - z.
class EdgeXYZPrior final : public BaseUnaryEdge<3, Eigen::Vector3d, VertexPointXYZ> {
 public:
  [[nodiscard]] ErrorVector evaluate(const Eigen::Vector3d& p) const override {
    return p - measurement();
  }
  void linearizeOplus() override;
};

}  // namespace graphslam::types_slam3d
