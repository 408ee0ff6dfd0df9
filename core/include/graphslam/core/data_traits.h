// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

namespace graphslam {

/// Flat-vector view of an estimate or measurement type, used for `.g2o` I/O, backups and
/// generic code. Specialise it for every estimate/measurement type that is not an Eigen
/// column vector or a double:
///   static constexpr int kDimension;                  // number of doubles
///   static void toData(const T& value, double* out);  // writes kDimension doubles
///   static T fromData(const double* in);              // reads kDimension doubles
template <typename T, typename Enable = void>
struct DataTraits;

template <int N>
struct DataTraits<Eigen::Matrix<double, N, 1>> {
  static_assert(N > 0, "DataTraits needs a fixed-size vector");
  static constexpr int kDimension = N;
  static void toData(const Eigen::Matrix<double, N, 1>& value, double* out) {
    Eigen::Map<Eigen::Matrix<double, N, 1>> target(out);
    target = value;
  }
  static Eigen::Matrix<double, N, 1> fromData(const double* in) {
    return Eigen::Map<const Eigen::Matrix<double, N, 1>>(in);
  }
};

template <>
struct DataTraits<double> {
  static constexpr int kDimension = 1;
  static void toData(double value, double* out) { *out = value; }
  static double fromData(const double* in) { return *in; }
};

}  // namespace graphslam
