// SPDX-License-Identifier: MIT
#pragma once

#include <cmath>
#include <sstream>

#include "graphslam/core/base_vertex.h"
#include "graphslam/core/data_traits.h"
#include "graphslam/geometry/se3.h"
#include "graphslam/support/error.h"

namespace graphslam {
/// An SE(3) transform as `.g2o` numbers: x y z qx qy qz qw. A quaternion whose norm is
/// within kQuaternionNormTolerance of 1 (files written with a few digits) is normalised on
/// reading; any other (zero, denormal, a typo) is refused: normalising it would make an
/// arbitrary rotation, and a zero one would drop the rotation term from the error.
template <>
struct DataTraits<geometry::SE3> {
  static constexpr int kDimension = 7;
  static constexpr double kQuaternionNormTolerance = 1e-2;
  static void toData(const geometry::SE3& v, double* out) {
    Eigen::Map<geometry::Vector7d> target(out);
    target = v.toVectorQT();
  }
  static geometry::SE3 fromData(const double* in) {
    const Eigen::Map<const geometry::Vector7d> v(in);
    const double norm = v.tail<4>().norm();
    if (!(std::abs(norm - 1.0) <= kQuaternionNormTolerance)) {
      std::ostringstream msg;
      msg.precision(6);
      msg << "the quaternion (qx qy qz qw) = (" << v[3] << " " << v[4] << " " << v[5] << " " << v[6]
          << ") has norm " << norm << ", not 1 (tolerance " << kQuaternionNormTolerance << ")";
      throw InputError(msg.str());
    }
    return geometry::SE3::fromVectorQT(v);
  }
};
}  // namespace graphslam

namespace graphslam::types_slam3d {

using geometry::SE3;

/// 3D robot pose — `.g2o` tag VERTEX_SE3:QUAT (x y z qx qy qz qw).
/// Update (6D, translation then rotation vector), applied on the right as g2o does:
/// X (+) d = X * (Exp(d_rot), d_trans), i.e. t + R d_trans, R Exp(d_rot).
class VertexSE3 final : public BaseVertex<6, SE3> {
 public:
  [[nodiscard]] SE3 plus(const SE3& x, const TangentVector& d) const override {
    return {x.so3() * geometry::SO3::exp(d.tail<3>()), x * Eigen::Vector3d(d.head<3>())};
  }
  /// d = (R0^T (t - t0), Log(R0^T R)): the inverse of plus.
  bool minusEstimate(const SE3& x, const SE3& from, TangentVector& d) const override {
    const geometry::SO3 r0_inv = from.so3().inverse();
    d << r0_inv * Eigen::Vector3d(x.translation() - from.translation()), (r0_inv * x.so3()).log();
    return true;
  }
};

/// 3D point — `.g2o` tag VERTEX_TRACKXYZ (x y z); the update adds.
class VertexPointXYZ final : public BaseVertex<3, Eigen::Vector3d> {
 public:
  [[nodiscard]] Eigen::Vector3d plus(const Eigen::Vector3d& x,
                                     const TangentVector& d) const override {
    return x + d;
  }
  bool minusEstimate(const Eigen::Vector3d& x, const Eigen::Vector3d& from,
                     TangentVector& d) const override {
    d = x - from;
    return true;
  }
};

}  // namespace graphslam::types_slam3d
