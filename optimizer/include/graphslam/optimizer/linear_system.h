// SPDX-License-Identifier: MIT
#pragma once

#include <memory>
#include <vector>

#include "graphslam/core/graph.h"
#include "graphslam/core/linear_solver.h"
#include "graphslam/diagnostics/graph_checks.h"
#include "graphslam/support/large_array.h"

namespace graphslam {

/// The linearisation of a graph's least-squares problem at the current estimates, in the
/// two forms a LinearSolver consumes:
///  - normal equations H dx = -g, H = sum J^T Omega J stored as the upper triangle with
///    full diagonal blocks (SparseStructure; the lower one in a solver's order after
///    reorder()), g = sum J^T Omega e;
///  - the whitened Jacobian J_w dx ~= -r_w with J_w = W J, r_w = W e, W^T W = Omega
///    (JacobianStructure, with one damping row per column at the bottom).
/// The active vertices are the non-fixed ones with at least one edge, in id order (or a
/// solver's order, reorder()); they get consecutive columns, which belong to this system
/// (blockStarts(), columnOf()): several systems on one graph do not disturb each other.
/// Structures are rebuilt only when the graph changes (vertices or edges added or removed,
/// fixed flags changed).
/// The optimizer uses this class; so can tools that study linear solvers on a graph's system.
class LinearSystem {
 public:
  LinearSystem();
  ~LinearSystem();
  LinearSystem(const LinearSystem&) = delete;
  LinearSystem& operator=(const LinearSystem&) = delete;

  /// Rebuilds the structures when `graph` changed since the last call (or on the first
  /// call). Returns whether it rebuilt. The graph must outlive this object's use.
  bool update(Graph& graph);
  /// Rebuilds H's structure with the active vertices in `block_order` (a permutation of
  /// them in id order: block_order[k] is the one placed at position k) and H stored as
  /// its lower triangle (LinearSolver::preferredBlockOrder); an empty order restores the
  /// id order and the upper triangle. The columns, the gradient and the diagonal
  /// positions follow. Returns false (and changes nothing) when `block_order`
  /// is not a permutation of the active vertices. Needs a prior update().
  bool reorder(const std::vector<int>& block_order);
  /// Whether H is stored in a solver's block order (reorder() with a permutation).
  [[nodiscard]] bool reordered() const;

  /// Threads for computeChi2() and linearize() (>= 1, the caller's included; default 1).
  /// The results are the same bits for every thread count: each edge writes only itself
  /// and sums run serially in edge order.
  void setThreads(int threads);
  [[nodiscard]] int threads() const;

  /// Calls computeError() of every active edge of `graph` and returns the objective: the sum of
  /// their robustChi2() in edge order (what Graph::chi2() returns when no edge has a
  /// robust kernel), in parallel with setThreads().
  double computeChi2(Graph& graph);
  /// Sum of chi2() = e^T Omega e of the errors stored by the last computeChi2() (robust
  /// kernels ignored), in edge order.
  [[nodiscard]] double rawChi2(const Graph& graph) const;

  /// Calls linearizeOplus() of every active edge (in parallel with setThreads(), except
  /// edges whose numeric Jacobian perturbs vertices in place: those run serially after
  /// the others). Errors must be current (computeChi2() or Graph::chi2() after the last
  /// change of the estimates).
  void linearize();
  /// Fills hessianValues() and gradient() from the stored errors and Jacobians.
  void assembleHessian();
  /// Fills jacobianValues(), residual() and gradient() (builds the Jacobian structure on
  /// first use); damping rows are zero.
  void assembleJacobian();

  [[nodiscard]] int dimension() const;
  [[nodiscard]] SparseStructure hessianStructure() const;
  [[nodiscard]] const support::LargeVector<double>& hessianValues() const { return h_values_; }
  [[nodiscard]] support::LargeVector<double>& mutableHessianValues() { return h_values_; }
  /// Positions of the diagonal entries of H inside the value array.
  [[nodiscard]] const std::vector<int>& hessianDiagonalPositions() const;

  [[nodiscard]] JacobianStructure jacobianStructure();
  [[nodiscard]] const std::vector<double>& jacobianValues() const { return j_values_; }
  [[nodiscard]] std::vector<double>& mutableJacobianValues() { return j_values_; }
  /// Position of the damping entry of every column inside the Jacobian value array.
  [[nodiscard]] const std::vector<int>& jacobianDampingPositions();
  /// Whitened residual, JacobianStructure::rows entries (damping rows zero).
  [[nodiscard]] const std::vector<double>& residual() const { return residual_; }

  /// J^T Omega e, dimension() entries (from the last assemble call).
  [[nodiscard]] const std::vector<double>& gradient() const { return gradient_; }

  [[nodiscard]] const std::vector<Vertex*>& activeVertices() const;
  /// The system's columns: activeVertices()[b] owns [blockStarts()[b], blockStarts()[b + 1]).
  [[nodiscard]] const std::vector<int>& blockStarts() const;
  /// First column of `v` in this system, -1 when it is not active (fixed, without edges or
  /// not in the graph). A look-up table is built at the first call after each build.
  [[nodiscard]] int columnOf(const Vertex& v) const;
  [[nodiscard]] const std::vector<Edge*>& activeEdges() const;
  /// Id of the vertex owning column `col`, -1 if out of range.
  [[nodiscard]] VertexId vertexOfColumn(int col) const;
  /// Connected groups of active vertices with no fixed vertex and no unary edge (their
  /// position is undetermined), each with up to `max_ids` ids: its anchor first (the lowest
  /// id among its vertices of the largest dimension), then the smallest.
  [[nodiscard]] std::vector<std::vector<VertexId>> unanchoredGroups(std::size_t max_ids = 20) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  support::LargeVector<double> h_values_;
  std::vector<double> j_values_;
  std::vector<double> residual_;
  std::vector<double> gradient_;
};

/// If no vertex is fixed and no edge is unary (nothing anchors the graph: relative
/// measurements leave a gauge freedom), fixes the vertex with edges that betterGaugeAnchor picks
/// and returns it; otherwise returns nullptr. The caller restores the flag when it wants.
Vertex* fixGaugeIfFree(Graph& graph);

}  // namespace graphslam
