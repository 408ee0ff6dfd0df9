// SPDX-License-Identifier: MIT
#pragma once

#include <string>

#include "graphslam/core/data_traits.h"

namespace graphslam {

using ParameterId = int;

/// A constant of the problem shared by many edges and defined once in a file, such as a
/// sensor's offset on the robot (g2o's `PARAMS_SE2OFFSET` / `PARAMS_SE3OFFSET` lines:
/// `TAG id values...`). Edges refer to parameters by id (Edge::parameterId); the Graph owns
/// them and resolves the ids when an edge is added. The optimizer never changes them.
///
/// Most types derive from `BaseParameter<Value>`; a type registers its tag with
/// `TypeRegistry::registerParameter<T>(tag)`.
class Parameter {
 public:
  Parameter() = default;
  virtual ~Parameter() = default;
  Parameter(const Parameter&) = delete;
  Parameter& operator=(const Parameter&) = delete;

  [[nodiscard]] ParameterId id() const { return id_; }
  /// Only before the parameter is added to a graph.
  void setId(ParameterId id) { id_ = id; }

  /// Number of doubles of the `.g2o` line after the id.
  [[nodiscard]] virtual int dataDimension() const = 0;
  virtual void getData(double* data) const = 0;
  /// May throw graphslam::Error for a value the type cannot take (the loader reports it with
  /// the file and line).
  virtual void setData(const double* data) = 0;

 private:
  ParameterId id_ = -1;
};

/// A parameter holding one value of type `ValueT` (an Eigen vector or any type with a
/// `DataTraits` specialisation, e.g. SE2 or an SE(3) pose).
template <typename ValueT>
class BaseParameter : public Parameter {
 public:
  using ValueType = ValueT;

  [[nodiscard]] const ValueType& value() const { return value_; }
  /// Only before edges that use the parameter are added: derived types may cache what the
  /// value implies (an inverse, a rotation matrix) in setValue.
  virtual void setValue(const ValueType& value) { value_ = value; }

  [[nodiscard]] int dataDimension() const final { return DataTraits<ValueType>::kDimension; }
  void getData(double* data) const final { DataTraits<ValueType>::toData(value_, data); }
  void setData(const double* data) final { setValue(DataTraits<ValueType>::fromData(data)); }

 private:
  ValueType value_{};
};

}  // namespace graphslam
