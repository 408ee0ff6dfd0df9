// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <vector>

#include "graphslam/core/base_multi_edge.h"
#include "graphslam/core/graph.h"
#include "graphslam/core/type_registry.h"

namespace graphslam::incremental {

/// A dense Gaussian prior on several vertices, linear in their tangent space at a fixed
/// linearisation point x_lin: what marginalising vertices leaves on the vertices that stay.
/// error = J * (x (-) x_lin) + r, with x (-) x_lin the tangent vectors of the vertices
/// (Vertex::minus) stacked in slot order, information the identity. So chi2 = |J d + r|^2
/// and at x = x_lin the edge adds J^T J to H and J^T r to the gradient. Its Jacobian of a
/// slot is J's columns of the slot times d(x (+) delta (-) x_lin)/d delta, which is the
/// identity for the additive updates (VERTEX_SE2, VERTEX_XY, ...) and is formed by central
/// differences of Vertex::minus in general (tested against the numeric Jacobian of the
/// error, core/jacobian_check.h). Not a type of the registry: the incremental optimizer
/// creates it, and its checkpoints hold it.
class LinearPriorEdge final : public BaseMultiEdge<Eigen::Dynamic, Eigen::VectorXd> {
 public:
  /// `dims`: the tangent dimension of each slot; `jacobian`: rows x sum(dims); `offset`: rows;
  /// `linearization_point`: the flat estimates of the slots, back to back. Then
  /// setVertexIds with one id per slot. Throws graphslam::Error when the sizes disagree.
  LinearPriorEdge(std::vector<int> dims, Eigen::MatrixXd jacobian, Eigen::VectorXd offset,
                  std::vector<double> linearization_point);

  [[nodiscard]] const std::vector<int>& slotDimensions() const { return dims_; }
  [[nodiscard]] const Eigen::MatrixXd& priorJacobian() const { return jacobian_; }
  [[nodiscard]] const Eigen::VectorXd& priorOffset() const { return offset_; }
  [[nodiscard]] const std::vector<double>& linearizationPoint() const { return x_lin_; }

  /// Throws graphslam::Error when a vertex's type does not define Vertex::minus.
  void computeError() override;
  void linearizeOplus() override;
  [[nodiscard]] bool perturbsVerticesInPlace() const override { return false; }
  [[nodiscard]] bool acceptsVertex(std::size_t slot, const Vertex& v) const override;
  [[nodiscard]] std::string expectedVertexType(std::size_t slot) const override;

 protected:
  void resizeForVertices(std::size_t num_vertices) override;

 private:
  /// x (+) step (-) x_lin of slot `slot`'s vertex into `delta`.
  void tangentOf(std::size_t slot, const double* step, double* delta) const;

  std::vector<int> dims_;
  std::vector<int> offsets_;  // first column of each slot in jacobian_
  // First entry of each slot in x_lin_: a cache, filled on first use (the estimate sizes
  // are known once the graph has resolved the vertices).
  mutable std::vector<int> data_offsets_;
  Eigen::MatrixXd jacobian_;
  Eigen::VectorXd offset_;
  std::vector<double> x_lin_;
};

/// What marginalizeVertices did.
struct Marginalization {
  std::vector<VertexId> separator;  ///< the vertices the new prior is on (by id)
  int removed_edges = 0;
  int prior_rank = 0;  ///< rows of the new prior (0: no prior added)
};

/// Marginalises `leaving` out of `graph`: the active edges touching them are linearised at
/// the current estimates into a dense H and gradient g over the leaving vertices M and the
/// free vertices S those edges also touch; the Schur complement H_SS - H_SM H_MM^+ H_MS and
/// g_S - H_SM H_MM^+ g_M (H_MM^+ the pseudo-inverse, eigenvalues below `rank_tolerance`
/// times the largest taken as zero) become one LinearPriorEdge on S (its directions with
/// eigenvalues below that fraction left out); then the leaving vertices and their edges
/// are removed. Fixed vertices of those edges are constants. Throws graphslam::Error for an
/// unknown id or a separator vertex whose type has no Vertex::minus (the graph unchanged).
Marginalization marginalizeVertices(Graph& graph, const std::vector<VertexId>& leaving,
                                    double rank_tolerance = 1e-12);

/// A copy of `graph` (graph_copy.h) without its marginalisation priors, which no file
/// format has a line for: to write or hand out a window's graph.
[[nodiscard]] Graph copyWithoutPriors(const Graph& graph, const TypeRegistry& types);

}  // namespace graphslam::incremental
