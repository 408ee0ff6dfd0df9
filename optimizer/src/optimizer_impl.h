// SPDX-License-Identifier: MIT
// The optimizer's state between iterations: the system in the form the linear solver
// consumes, its (damped) factorisation and solve, the update of the estimates and its undo.
// The step strategies (minimizer/) compute steps through it. Private to graphslam::core.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "graphslam/core/linear_solver.h"
#include "graphslam/optimizer/linear_system.h"
#include "graphslam/optimizer/optimizer.h"

namespace graphslam {

struct Optimizer::Impl {
  LinearSystem structure;
  std::unique_ptr<LinearSolver> solver;
  std::string solver_name;
  bool analyzed = false;
  bool jacobian_form = false;
  std::vector<double> rhs;
  std::vector<double> dx;
  std::vector<double> saved_diag;  // diagonal of the undamped H
  std::vector<double> damping_diag;
  bool diagonal_damped = false;  // H's diagonal holds saved_diag + lambda * damping_diag

  /// Fills the system of the form the solver consumes from the stored Jacobians.
  void assemble() {
    diagonal_damped = false;
    if (jacobian_form) {
      structure.assembleJacobian();
      rhs.resize(structure.residual().size());
      for (std::size_t i = 0; i < rhs.size(); ++i) rhs[i] = -structure.residual()[i];
    } else {
      structure.assembleHessian();
      rhs.resize(structure.gradient().size());
      for (std::size_t i = 0; i < rhs.size(); ++i) rhs[i] = -structure.gradient()[i];
    }
  }

  /// Diagonal of the undamped H = J^T Omega J, into saved_diag.
  void saveDiagonal() {
    const int n = structure.dimension();
    saved_diag.assign(static_cast<std::size_t>(n), 0.0);
    if (jacobian_form) {
      const JacobianStructure js = structure.jacobianStructure();
      const auto& v = structure.jacobianValues();
      for (int c = 0; c < n; ++c) {
        double sum = 0.0;
        for (int k = js.col_ptr[c]; k < js.col_ptr[c + 1]; ++k) {
          if (js.row_idx[k] < js.damping_row) sum += v[k] * v[k];
        }
        saved_diag[c] = sum;
      }
    } else {
      const auto& diag = structure.hessianDiagonalPositions();
      for (int i = 0; i < n; ++i) saved_diag[i] = structure.hessianValues()[diag[i]];
    }
  }

  /// Symbolic analysis; for a normal-equations solver first H's layout: the optimizer's
  /// order, or the block order the solver asks for (LinearSolver::preferredBlockOrder).
  LinearSolverResult analyze() {
    if (jacobian_form) return solver->analyzeJacobian(structure.jacobianStructure());
    structure.reorder({});  // the solver is shown H in the id order
    const std::vector<int> order = solver->preferredBlockOrder(structure.hessianStructure());
    if (!order.empty() && !structure.reorder(order)) {
      return LinearSolverResult::failure(
          LinearSolverStatus::kFailure,
          "solver " + solver->name() +
              " asked for a block order that is not a permutation of the " +
              std::to_string(structure.activeVertices().size()) + " vertices");
    }
    return solver->analyze(structure.hessianStructure());
  }

  /// Factorises the system with damping lambda * damping_diag (none when lambda is 0).
  /// Damping needs saveDiagonal() and damping_diag of the current linearisation.
  LinearSolverResult factorize(double lambda) {
    const int n = structure.dimension();
    if (jacobian_form) {
      auto& v = structure.mutableJacobianValues();
      const auto& pos = structure.jacobianDampingPositions();
      for (int i = 0; i < n; ++i) {
        v[pos[i]] = lambda > 0 ? std::sqrt(lambda * damping_diag[i]) : 0.0;
      }
      return solver->factorizeJacobian(v.data());
    }
    auto& v = structure.mutableHessianValues();
    const auto& diag = structure.hessianDiagonalPositions();
    if (lambda > 0) {
      for (int i = 0; i < n; ++i) v[diag[i]] = saved_diag[i] + lambda * damping_diag[i];
      diagonal_damped = true;
    } else if (diagonal_damped) {
      for (int i = 0; i < n; ++i) v[diag[i]] = saved_diag[i];
      diagonal_damped = false;
    }
    return solver->factorize(v.data());
  }

  LinearSolverResult solve() {
    return jacobian_form ? solver->solveJacobian(rhs.data(), dx.data())
                         : solver->solve(rhs.data(), dx.data());
  }

  /// The objective (sum of robust chi2) at the current estimates; stores every error.
  double evalChi2(Graph& graph) { return structure.computeChi2(graph); }

  void applyUpdate() {
    const auto& vertices = structure.activeVertices();
    const auto& starts = structure.blockStarts();
    for (std::size_t b = 0; b < vertices.size(); ++b) {
      vertices[b]->push();
      vertices[b]->oplus(dx.data() + starts[b]);
    }
  }
  void undoUpdate() {
    for (Vertex* v : structure.activeVertices()) v->pop();
  }

  /// Flat copy of the estimates of all active vertices.
  void saveState(std::vector<double>& state) const {
    state.clear();
    std::vector<double> buf;
    for (const Vertex* v : structure.activeVertices()) {
      buf.resize(static_cast<std::size_t>(v->estimateDataDimension()));
      v->getEstimateData(buf.data());
      state.insert(state.end(), buf.begin(), buf.end());
    }
  }
  void restoreState(const std::vector<double>& state) {
    std::size_t k = 0;
    for (Vertex* v : structure.activeVertices()) {
      v->setEstimateData(state.data() + k);
      k += static_cast<std::size_t>(v->estimateDataDimension());
    }
  }
};

}  // namespace graphslam
