// SPDX-License-Identifier: MIT
// The optimizer's state between iterations and the steps it computes from it: the system
// in the form the linear solver consumes, the damped factorisation, chord steps (conjugate
// gradients preconditioned with the last factorisation) and the first iteration's dogleg
// step. Private to optimizer.cpp.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "graphslam/core/linear_solver.h"
#include "graphslam/core/linear_system.h"
#include "graphslam/core/optimizer.h"

namespace graphslam {

struct Optimizer::Impl {
  LinearSystem structure;
  std::unique_ptr<LinearSolver> solver;
  std::string solver_name;
  bool analyzed = false;
  bool jacobian_form = false;
  std::vector<double> rhs;
  std::vector<double> dx;
  std::vector<double> gn_dx, cauchy;  // the first iteration's dogleg: the ends of its path
  std::vector<double> saved_diag;     // diagonal of the undamped H
  std::vector<double> damping_diag;
  std::vector<double> cg_zhp, cg_p;  // chord steps' conjugate gradients (r lives in rhs)

  /// Fills the system of the form the solver consumes from the stored Jacobians.
  void assemble() {
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
    if (lambda > 0) {
      const auto& diag = structure.hessianDiagonalPositions();
      for (int i = 0; i < n; ++i) v[diag[i]] = saved_diag[i] + lambda * damping_diag[i];
    }
    return solver->factorize(v.data());
  }

  LinearSolverResult solve() {
    return jacobian_form ? solver->solveJacobian(rhs.data(), dx.data())
                         : solver->solve(rhs.data(), dx.data());
  }

  /// y = H x, H the assembled Hessian (its stored triangle; the other triangles of the
  /// diagonal blocks, also stored, are skipped: in every column they are the entries past
  /// the diagonal of an upper H, before it in a lower one).
  void hessianProduct(const std::vector<double>& x, std::vector<double>& y) const {
    const SparseStructure h = structure.hessianStructure();
    const double* v = structure.hessianValues().data();
    const int* diag = structure.hessianDiagonalPositions().data();
    y.assign(x.size(), 0.0);
    const double* xv = x.data();
    double* yv = y.data();
    for (int c = 0; c < h.n; ++c) {
      const int first = h.lower ? diag[c] + 1 : h.col_ptr[c];
      const int last = h.lower ? h.col_ptr[c + 1] : diag[c];
      const double xc = xv[c];
      double yc = v[diag[c]] * xc;
      for (int k = first; k < last; ++k) {
        const int r = h.row_idx[k];
        yc += v[k] * xv[r];
        yv[r] += v[k] * xc;
      }
      yv[c] += yc;
    }
  }

  /// Conjugate-gradient iterations a chord step may take: a factorisation costs at least
  /// nnz(L)/n / 4 solves (sum c_j^2 flops against 4 sum c_j, c_j the column counts of L);
  /// a chord step may spend half of that, at least one iteration and at most
  /// `max_iterations`.
  int chordIterations(int max_iterations) const {
    const double n = std::max(1, structure.dimension());
    const double per_column = static_cast<double>(solver->factorNonZeros()) / n;
    return std::clamp(static_cast<int>(per_column / 6.0), 1, max_iterations);
  }

  /// Chord step: solves H dx = rhs (the Hessian just assembled) by conjugate gradients
  /// preconditioned with the solver's last factorisation, of an earlier H. The first
  /// iteration is the plain chord step scaled to the minimum of the model along it.
  /// Iteration k lowers the model's chi2 by alpha_k r_k^T M^-1 r_k; the iterations stop
  /// when that is below max(relative_tolerance times the first one's, absolute_tolerance)
  /// (the decreases shrink geometrically), or after max_iterations. Returns the iterations
  /// made (0: a solve failed) and whether the tolerance was reached.
  std::pair<int, bool> chordSolve(double relative_tolerance, double absolute_tolerance,
                                  int max_iterations) {
    const std::size_t n = rhs.size();
    // The residual r starts as rhs and is updated in rhs's array (rhs is -gradient: it is
    // restored on return); z = M^-1 r is dead once p is updated, and H p takes its place
    // (cg_zhp): two vectors of n less at the memory peak of large systems.
    struct RestoreRhs {
      Impl& im;
      ~RestoreRhs() {
        const auto& g = im.structure.gradient();
        for (std::size_t i = 0; i < im.rhs.size(); ++i) im.rhs[i] = -g[i];
      }
    } restore{*this};
    std::vector<double>& cg_r = rhs;
    dx.assign(n, 0.0);
    cg_p.assign(n, 0.0);
    std::vector<double>& cg_z = cg_zhp;
    std::vector<double>& cg_hp = cg_zhp;
    cg_z.resize(n);
    double rz_old = 0.0;
    double first_decrease = 0.0;
    for (int k = 1; k <= max_iterations; ++k) {
      if (!solver->solve(cg_r.data(), cg_z.data()).ok()) return {0, false};
      double rz = 0.0;
      for (std::size_t i = 0; i < n; ++i) rz += cg_r[i] * cg_z[i];
      const double beta = k == 1 ? 0.0 : rz / rz_old;
      for (std::size_t i = 0; i < n; ++i) cg_p[i] = cg_z[i] + beta * cg_p[i];
      hessianProduct(cg_p, cg_hp);
      double php = 0.0;
      for (std::size_t i = 0; i < n; ++i) php += cg_p[i] * cg_hp[i];
      if (!(php > 0.0 && rz > 0.0 && std::isfinite(php) && std::isfinite(rz))) {
        return {k - 1, rz == 0.0 && k > 1};  // at the solution (or broken down)
      }
      const double alpha = rz / php;
      for (std::size_t i = 0; i < n; ++i) {
        dx[i] += alpha * cg_p[i];
        cg_r[i] -= alpha * cg_hp[i];
      }
      const double decrease = alpha * rz;
      if (k == 1) first_decrease = decrease;
      if (decrease <= std::max(relative_tolerance * first_decrease, absolute_tolerance)) {
        return {k, true};
      }
      rz_old = rz;
    }
    return {max_iterations, false};
  }

  double evalChi2(Graph& graph) { return structure.computeChi2(graph); }

  /// Dogleg step from the undamped step in dx (which raised chi2 from `chi2` to
  /// `gn_chi2`; not applied), with the same factorisation: the path runs from the origin
  /// along the steepest descent of chi2 scaled by D = diag(H) to its minimum (the Cauchy
  /// point), then straight to the Gauss-Newton step. Its point at D-norm Delta, Delta the
  /// Gauss-Newton step's halved again and again, is tried until the quadratic model
  /// predicts the decrease of chi2 within `agreement` (each trial: one evaluation of
  /// chi2); after `max_halvings` the lowest chi2 seen is taken, if it is below gn_chi2.
  /// The first trial skips a halving when the Gauss-Newton step's own chi2 says so:
  /// chi2 interpolated along that step by a parabola (chi2 and its slope at the origin,
  /// gn_chi2 at the step) has its minimum at 1 / (2 - rho) of the step, rho the step's
  /// actual over predicted decrease (Dennis and Schnabel's backtracking rule). At or below
  /// a quarter (rho <= -2: the step raised chi2 by at least twice the decrease its model
  /// promised), the first trial is at a quarter; the trust radius never shrinks more than
  /// four times at once (Nocedal and Wright's factor).
  /// Applies the step taken and returns {its chi2, halvings, trials} ({gn_chi2, 0, ...}:
  /// the undamped step, when no trial is lower or the path is undefined).
  struct DoglegResult {
    double chi2;
    int halvings;
    int trials;
  };
  DoglegResult firstStepDogleg(Graph& graph, double chi2, double gn_chi2, double agreement,
                               int max_halvings) {
    const int n = structure.dimension();
    const auto& g = structure.gradient();
    const auto& h = structure.hessianValues();
    const auto& diag = structure.hessianDiagonalPositions();
    gn_dx = dx;
    const auto scale = [&](int i) { return std::clamp(h[diag[i]], 1e-6, 1e32); };  // D's entries
    // Cauchy point c = -a D^-1 g, a = g^T D^-1 g / (D^-1 g)^T H (D^-1 g).
    cauchy.resize(static_cast<std::size_t>(n));
    std::vector<double>& hc = cg_zhp;  // H (D^-1 g), scratch
    double gdg = 0.0;
    for (int i = 0; i < n; ++i) {
      cauchy[i] = -g[i] / scale(i);
      gdg -= g[i] * cauchy[i];
    }
    hessianProduct(cauchy, hc);
    double chc = 0.0;
    for (int i = 0; i < n; ++i) chc += cauchy[i] * hc[i];
    const double a = gdg / chc;
    if (!(a > 0.0) || !std::isfinite(a)) {
      applyUpdate();
      return {gn_chi2, 0, 0};
    }
    for (int i = 0; i < n; ++i) cauchy[i] *= a;
    chc *= a * a;
    // Scalars of the path: D-norms, g^T c, g^T s (s the Gauss-Newton step: H s = -g,
    // so s^T H s = -g^T s and c^T H s = -g^T c).
    double cc = 0.0, cs = 0.0, ss = 0.0, gc = 0.0, gs = 0.0;
    for (int i = 0; i < n; ++i) {
      const double d = scale(i);
      cc += d * cauchy[i] * cauchy[i];
      cs += d * cauchy[i] * gn_dx[i];
      ss += d * gn_dx[i] * gn_dx[i];
      gc += g[i] * cauchy[i];
      gs += g[i] * gn_dx[i];
    }
    const double gn_norm = std::sqrt(ss);
    const double c_norm = std::sqrt(cc);
    // The point at D-norm delta: (1 - t) c + t s, or u c (u <= 1) inside the Cauchy point;
    // and the model's decrease of chi2 there, -2 g^T p - p^T H p.
    auto point = [&](double delta, double& predicted) {
      if (delta <= c_norm) {
        const double u = delta / c_norm;
        for (int i = 0; i < n; ++i) dx[i] = u * cauchy[i];
        predicted = -2.0 * u * gc - u * u * chc;
        return;
      }
      const double qa = cc - 2.0 * cs + ss;  // |s - c|^2
      const double qb = 2.0 * (cs - cc);
      const double qc = cc - delta * delta;
      const double t = (-qb + std::sqrt(std::max(0.0, qb * qb - 4.0 * qa * qc))) / (2.0 * qa);
      for (int i = 0; i < n; ++i) dx[i] = (1.0 - t) * cauchy[i] + t * gn_dx[i];
      const double gp = (1.0 - t) * gc + t * gs;
      const double php = (1.0 - t) * (1.0 - t) * chc - 2.0 * t * (1.0 - t) * gc - t * t * gs;
      predicted = -2.0 * gp - php;
    };
    // gs = g^T s < 0 is minus the model's decrease of chi2 by s; rho <= -2 is
    // gn_chi2 - chi2 >= 2 (-gs). A non-finite gn_chi2 counts as that too.
    const bool far_off = !(gn_chi2 - chi2 < -2.0 * gs);
    double best_chi2 = gn_chi2;
    int best = 0;
    int trials = 0;
    for (int k = far_off ? 2 : 1; k <= max_halvings; ++k) {
      double predicted = 0.0;
      point(std::ldexp(gn_norm, -k), predicted);
      applyUpdate();
      const double trial = evalChi2(graph);
      ++trials;
      if (trial < best_chi2) {
        best_chi2 = trial;
        best = k;
      }
      if (std::abs(1.0 - (chi2 - trial) / predicted) <= agreement) {
        return {trial, k, trials};
      }
      undoUpdate();
    }
    if (best == 0) {
      dx = gn_dx;
    } else {
      double predicted = 0.0;
      point(std::ldexp(gn_norm, -best), predicted);
    }
    applyUpdate();
    return {evalChi2(graph), best, trials};
  }

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
