// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

#include "graphslam/core/parameter.h"
#include "graphslam/types_slam2d/se2.h"

namespace graphslam::types_slam2d {

/// A sensor's pose on the robot, robot_T_sensor — `.g2o` line `PARAMS_SE2OFFSET id x y theta`
/// (g2o's tag and layout), shared by the edges that name its id (EDGE_SE2_OFFSET,
/// EDGE_SE2_POINTXY_OFFSET). Its inverse and rotation matrix are computed once, when the
/// value is set.
class ParameterSE2Offset final : public BaseParameter<SE2> {
 public:
  void setValue(const SE2& offset) override {
    BaseParameter<SE2>::setValue(offset);
    inverse_ = offset.inverse();
    rotation_ = offset.rotation();
  }
  /// robot_T_sensor.
  [[nodiscard]] const SE2& offset() const { return value(); }
  /// sensor_T_robot.
  [[nodiscard]] const SE2& inverse() const { return inverse_; }
  /// The offset's rotation matrix.
  [[nodiscard]] const Eigen::Matrix2d& rotation() const { return rotation_; }

 private:
  SE2 inverse_;
  Eigen::Matrix2d rotation_ = Eigen::Matrix2d::Identity();
};

}  // namespace graphslam::types_slam2d
