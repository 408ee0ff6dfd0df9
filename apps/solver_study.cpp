// SPDX-License-Identifier: MIT
// graphslam solvers' study: a graph's linear system and timed runs of one solver on it.
#include "solver_study.h"

#include <algorithm>
#include <chrono>

#include "graphslam/optimizer/linear_system.h"

namespace graphslam::apps {

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

}  // namespace

StudySystem linearSystemOf(Graph& graph) {
  LinearSystem ls;
  ls.update(graph);
  (void)graph.chi2();  // current errors
  ls.linearize();
  StudySystem s;
  s.n = ls.dimension();
  const SparseStructure hs = ls.hessianStructure();
  s.num_blocks = hs.num_blocks;
  s.h_ptr.assign(hs.col_ptr, hs.col_ptr + hs.n + 1);
  s.h_idx.assign(hs.row_idx, hs.row_idx + hs.nnz());
  s.block_starts.assign(hs.block_starts, hs.block_starts + hs.num_blocks + 1);
  ls.assembleHessian();
  s.h_values.assign(ls.hessianValues().begin(), ls.hessianValues().end());
  s.gradient = ls.gradient();
  s.j = ls.jacobianStructure();
  s.j_ptr.assign(s.j.col_ptr, s.j.col_ptr + s.j.cols + 1);
  s.j_idx.assign(s.j.row_idx, s.j.row_idx + s.j.nnz());
  ls.assembleJacobian();
  s.j_values = ls.jacobianValues();
  s.residual = ls.residual();
  for (std::size_t b = 0; b < ls.activeVertices().size(); ++b)
    s.columns.emplace_back(ls.activeVertices()[b], ls.blockStarts()[b]);
  return s;
}

Row runSolver(const SolverRegistry& registry, const std::string& name, Ordering ordering,
              const StudySystem& sys, int repeats, bool want_pattern, int refine) {
  Row row;
  row.solver = name;
  row.ordering = toString(ordering);
  LinearSolverOptions options;
  options.ordering = ordering;
  std::vector<double> ta, tf, ts, tr;
  for (int rep = 0; rep < repeats; ++rep) {
    auto solver = registry.create(name, options);
    const bool jac = solver->form() == SystemForm::kJacobian;
    row.form = jac ? "J" : "H";
    std::vector<double> rhs;
    if (jac) {
      rhs = sys.residual;
    } else {
      rhs = sys.gradient;
    }
    for (double& v : rhs) v = -v;
    row.x.assign(static_cast<std::size_t>(sys.n), 0.0);
    auto t = Clock::now();
    LinearSolverResult r =
        jac ? solver->analyzeJacobian(sys.jacobian()) : solver->analyze(sys.hessian());
    ta.push_back(since(t));
    if (r.ok()) {
      t = Clock::now();
      r = jac ? solver->factorizeJacobian(sys.j_values.data())
              : solver->factorize(sys.h_values.data());
      tf.push_back(since(t));
    }
    if (r.ok()) {
      t = Clock::now();
      r = jac ? solver->solveJacobian(rhs.data(), row.x.data())
              : solver->solve(rhs.data(), row.x.data());
      ts.push_back(since(t));
      row.x_unrefined = row.x;
      // Iterative refinement of the normal equations with the gradient computed from J
      // (corrected semi-normal equations): x -= H^-1 J^T (J x + r). Timed on its own: the
      // solve above is what every other solver (and SciPy's spsolve) does.
      t = Clock::now();
      std::vector<double> res, corr(row.x.size());
      for (int step = 0; r.ok() && !jac && step < refine; ++step) {
        sys.gradientFromJacobian(row.x, res);
        for (double& v : res) v = -v;
        r = solver->solve(res.data(), corr.data());
        for (std::size_t i = 0; i < corr.size(); ++i) row.x[i] += corr[i];
      }
      tr.push_back(since(t));
    }
    if (!r.ok()) {
      row.status = std::string(toString(r.status)) + (r.message.empty() ? "" : ": " + r.message);
      if (r.column >= 0) row.status += " (column " + std::to_string(r.column) + ")";
      break;
    }
    row.factor_nnz = solver->factorNonZeros();
    if (want_pattern && rep + 1 == repeats) {
      if (!solver->factorPattern(row.factor_ptr, row.factor_idx)) {
        row.factor_ptr.clear();
        row.factor_idx.clear();
      }
    }
  }
  row.analyze = median(ta);
  row.factorize = median(tf);
  row.solve = median(ts);
  row.refine = median(tr);
  if (row.ok()) row.residual = sys.relativeResidual(row.x);
  return row;
}

}  // namespace graphslam::apps
