// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

namespace graphslam {

using VertexId = int;

class Edge;
class Graph;
namespace detail {
class HessianStructure;
}  // namespace detail

/// A variable of the optimisation problem: an estimate living on a manifold of tangent
/// dimension `dimension()`, updated by `oplus(delta)`.
///
/// Most types derive from `BaseVertex<D, Estimate>`, which implements everything here
/// except the retraction `plus()`.
class Vertex {
 public:
  explicit Vertex(int dimension) : dimension_(dimension) {}
  virtual ~Vertex() = default;
  Vertex(const Vertex&) = delete;
  Vertex& operator=(const Vertex&) = delete;

  [[nodiscard]] VertexId id() const { return id_; }
  /// Only before the vertex is added to a graph.
  void setId(VertexId id) { id_ = id; }

  /// A fixed vertex is held constant by the optimizer (it has no columns in H).
  [[nodiscard]] bool fixed() const { return fixed_; }
  void setFixed(bool fixed) { fixed_ = fixed; }

  /// Tangent-space (update) dimension.
  [[nodiscard]] int dimension() const { return dimension_; }

  /// Number of doubles of the flat estimate representation (what a `.g2o` line holds).
  [[nodiscard]] virtual int estimateDataDimension() const = 0;
  virtual void getEstimateData(double* data) const = 0;
  virtual void setEstimateData(const double* data) = 0;

  /// Values of the vertex's `.g2o` line after the estimate that are not estimated: constants
  /// of the problem such as a timestamp. The optimizer never reads or changes them (they
  /// are not part of push/pop or the flat estimate). Default: none.
  [[nodiscard]] virtual int parameterDataDimension() const { return 0; }
  virtual void getParameterData(double* /*data*/) const {}
  /// May throw graphslam::Error for a value the type cannot take (the loader reports it
  /// with the file and line).
  virtual void setParameterData(const double* /*data*/) {}

  /// x <- x (+) delta, with `delta` of length `dimension()`.
  virtual void oplus(const double* delta) = 0;
  /// The inverse of the update: writes delta (length `dimension()`) with
  /// from (+) delta = x (+) step, where `from` is a flat estimate of this type and `step`
  /// a tangent vector (nullptr: zero). False when the type does not define it (the
  /// default); the built-in types do. Pure: the estimate is not changed. Used by the
  /// marginalisation priors of the incremental optimizer (incremental/linear_prior_edge.h).
  [[nodiscard]] virtual bool minus(const double* /*from*/, const double* /*step*/,
                                   double* /*delta*/) const {
    return false;
  }

  /// Single-level backup of the estimate (used by the optimizer to undo rejected steps).
  virtual void push() = 0;
  virtual void pop() = 0;

  /// Edges incident to this vertex (maintained by the owning Graph).
  [[nodiscard]] const std::vector<Edge*>& edges() const { return edges_; }

  // A vertex's columns in a linear system belong to that system
  // (LinearSystem::columnOf, LinearSystem::blockStarts): several systems may be built on
  // one graph, each with its own order.

 private:
  friend class Graph;
  friend class detail::HessianStructure;
  VertexId id_ = -1;
  int dimension_;
  bool fixed_ = false;
  /// Scratch of HessianStructure::build only: the vertex's block while the structure is
  /// built (-1: not active). Not meaningful outside that call.
  int build_block_ = -1;
  std::vector<Edge*> edges_;
};

}  // namespace graphslam
