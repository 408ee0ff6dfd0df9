// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/core/parameter.h"
#include "graphslam/types_slam3d/vertex_se3.h"

namespace graphslam::types_slam3d {

/// A sensor's pose on the robot — `.g2o` tag PARAMS_SE3OFFSET (id x y z qx qy qz qw).
/// Edges that refer to it measure from the sensor frame X * offset.
class ParameterSE3Offset final : public BaseParameter<SE3> {
 public:
  void setValue(const SE3& offset) override {
    BaseParameter<SE3>::setValue(offset);
    inverse_ = offset.inverse();
  }
  [[nodiscard]] const SE3& offset() const { return value(); }
  [[nodiscard]] const SE3& inverseOffset() const { return inverse_; }

 private:
  SE3 inverse_;
};

}  // namespace graphslam::types_slam3d
