// SPDX-License-Identifier: MIT
#include "graphslam/core/optimizer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

#include "graphslam/core/error.h"
#include "graphslam/core/linear_system.h"
#include "graphslam/core/logging.h"
#include "hessian_structure.h"
#include "timing.h"

namespace graphslam {

const char* toString(Algorithm algorithm) {
  switch (algorithm) {
    case Algorithm::kGaussNewton:
      return "gauss-newton";
    case Algorithm::kLevenbergMarquardt:
      return "levenberg-marquardt";
    case Algorithm::kGaussNewtonFallback:
      return "gauss-newton with lm fallback";
  }
  return "?";
}

const char* toString(TerminationStatus status) {
  switch (status) {
    case TerminationStatus::kConverged:
      return "converged";
    case TerminationStatus::kMaxIterations:
      return "maximum iterations reached";
    case TerminationStatus::kNoProgress:
      return "no progress";
    case TerminationStatus::kNumericalFailure:
      return "numerical failure";
    case TerminationStatus::kUnderDetermined:
      return "under-determined";
  }
  return "?";
}

TimeSplit& TimeSplit::operator+=(const TimeSplit& o) {
  linearize += o.linearize;
  build += o.build;
  factorize += o.factorize;
  solve += o.solve;
  return *this;
}

std::string Summary::report() const {
  std::ostringstream s;
  s.precision(10);
  s << "status:        " << toString(status);
  if (!message.empty()) s << " (" << message << ")";
  s << "\nalgorithm:     " << toString(algorithm) << ", linear solver " << linear_solver
    << "\nproblem:       " << num_vertices << " free vertices, " << num_edges << " edges, "
    << system_dimension << " unknowns, nnz(H) " << hessian_nonzeros << ", nnz(L) "
    << factor_nonzeros << "\nchi2:          " << initial_chi2 << " -> " << final_chi2
    << "\niterations:    " << iterations;
  s.precision(4);
  s << "\ntime:          " << total_time << " s (linearize " << time.linearize << ", build "
    << time.build << ", factorize " << time.factorize << ", solve " << time.solve << ")";
  if (!gauge_fixed.empty()) {
    s << "\ngauge:         fixed vertex";
    for (VertexId id : gauge_fixed) s << ' ' << id;
  }
  for (const auto& group : unanchored) {
    s << "\nunanchored:    vertices";
    for (VertexId id : group) s << ' ' << id;
  }
  return s.str();
}

using detail::Clock;
using detail::seconds;

namespace {
/// Smallest LM damping, relative to the scale of the initial one (the largest diagonal
/// entry of H for identity damping, 1 for diagonal damping).
constexpr double kMinRelativeLambda = 1e-16;
/// A Gauss-Newton step that lowered chi2 by less than this fraction is followed by a
/// chord step (the last factorisation reused) before a new factorisation.
constexpr double kChordTrigger = 1e-4;
/// So is a step (Gauss-Newton or chord) whose actual decrease of chi2 was within this
/// fraction of its quadratic model's (the problem is that close to linear around it),
/// when the chord step may take at least kChordAgreementIterations conjugate-gradient
/// iterations: far from convergence one chord iteration gains much less than a
/// Gauss-Newton step, a few preconditioned ones gain as much.
constexpr double kChordAgreement = 0.05;
constexpr int kChordAgreementIterations = 4;
/// A chord step solves the new system by conjugate gradients preconditioned with the last
/// factorisation, until an iteration lowers the model by less than this fraction of
/// what the first one did...
constexpr double kChordRelativeTolerance = 1e-4;
/// ...or below this fraction of the optimizer's function tolerance times chi2.
constexpr double kChordAbsoluteTolerance = 0.1;
/// Conjugate-gradient iterations a chord step may take: a factorisation costs at least
/// nnz(L)/n / 4 solves (sum c_j^2 flops against 4 sum c_j, c_j the column counts of L);
/// a chord step may spend half of that, at least one iteration and at most this many.
constexpr int kChordMaxIterations = 10;
/// The first iteration's dogleg step (firstStepDogleg) is the first trial point whose
/// actual decrease of chi2 is within this fraction of the model's, or the lowest after
/// this many halvings of the trust region.
constexpr double kDoglegAgreement = 0.25;
constexpr int kDoglegMaxHalvings = 20;
}  // namespace

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

  /// Conjugate-gradient iterations a chord step may take (kChordMaxIterations).
  int chordIterations() const {
    const double n = std::max(1, structure.dimension());
    const double per_column = static_cast<double>(solver->factorNonZeros()) / n;
    return std::clamp(static_cast<int>(per_column / 6.0), 1, kChordMaxIterations);
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
  /// predicts the decrease of chi2 within kDoglegAgreement (each trial: one evaluation of
  /// chi2); after kDoglegMaxHalvings the lowest chi2 seen is taken, if it is below gn_chi2.
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
  DoglegResult firstStepDogleg(Graph& graph, double chi2, double gn_chi2) {
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
    for (int k = far_off ? 2 : 1; k <= kDoglegMaxHalvings; ++k) {
      double predicted = 0.0;
      point(std::ldexp(gn_norm, -k), predicted);
      applyUpdate();
      const double trial = evalChi2(graph);
      ++trials;
      if (trial < best_chi2) {
        best_chi2 = trial;
        best = k;
      }
      if (std::abs(1.0 - (chi2 - trial) / predicted) <= kDoglegAgreement) {
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
    for (Vertex* v : structure.activeVertices()) {
      v->push();
      v->oplus(dx.data() + v->hessianIndex());
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

Optimizer::Optimizer(Graph& graph, const SolverRegistry& solvers, Options options)
    : graph_(graph),
      solvers_(solvers),
      options_(std::move(options)),
      impl_(std::make_unique<Impl>()) {
  impl_->solver = solvers_.create(options_.linear_solver);
  impl_->solver_name = options_.linear_solver;
}

Optimizer::Optimizer(Graph& graph, const SolverRegistry& solvers)
    : Optimizer(graph, solvers, Options{}) {}

Optimizer::~Optimizer() = default;

double Optimizer::chi2() { return impl_->evalChi2(graph_); }

Summary Optimizer::optimize() {
  const auto t_start = Clock::now();
  Impl& im = *impl_;
  Summary summary;
  summary.algorithm = options_.algorithm;
  summary.linear_solver = options_.linear_solver;
  if (im.solver_name != options_.linear_solver) {
    im.solver = solvers_.create(options_.linear_solver);
    im.solver_name = options_.linear_solver;
    im.analyzed = false;
  }

  // Gauge: with nothing fixed and no unary edge, the whole graph can move freely.
  const detail::GaugeFix gauge(graph_, options_.fix_gauge);
  summary.gauge_fixed = gauge.fixedIds();
  for (VertexId id : summary.gauge_fixed) {
    log(LogLevel::kInfo, "no vertex is fixed and no prior exists: fixing vertex " +
                             std::to_string(id) + " (the lowest id) to remove the gauge freedom");
  }

  TimeSplit setup;
  auto t0 = Clock::now();
  im.structure.setThreads(options_.threads);
  if (im.structure.update(graph_)) im.analyzed = false;
  im.jacobian_form = im.solver->form() == SystemForm::kJacobian;
  summary.num_vertices = im.structure.activeVertices().size();
  summary.num_edges = graph_.numEdges();
  summary.system_dimension = im.structure.dimension();
  summary.hessian_nonzeros = im.structure.hessianStructure().nnz();

  summary.unanchored = im.structure.unanchoredGroups();
  for (const auto& group : summary.unanchored) {
    std::string ids;
    for (VertexId id : group) ids += " " + std::to_string(id);
    log(LogLevel::kWarning,
        "vertices with no anchor (no fixed vertex, no prior) — their position is undetermined:" +
            ids);
  }

  summary.initial_chi2 = im.evalChi2(graph_);
  summary.final_chi2 = summary.initial_chi2;
  if (im.structure.dimension() == 0) {
    summary.status = TerminationStatus::kConverged;
    summary.message = "no free vertex with an edge: nothing to optimise";
    summary.total_time = seconds(t_start, Clock::now());
    return summary;
  }
  if (!std::isfinite(summary.initial_chi2)) {
    summary.status = TerminationStatus::kNumericalFailure;
    summary.message = "initial chi2 is not finite";
    summary.total_time = seconds(t_start, Clock::now());
    return summary;
  }
  if (!im.analyzed) {
    const LinearSolverResult r = im.analyze();
    if (!r.ok()) {
      summary.status = TerminationStatus::kNumericalFailure;
      summary.message = "symbolic analysis failed: " + r.message;
      summary.total_time = seconds(t_start, Clock::now());
      return summary;
    }
    im.analyzed = true;
  }
  setup.build += seconds(t0, Clock::now());
  summary.time += setup;

  const int n = im.structure.dimension();
  im.dx.resize(static_cast<std::size_t>(n));
  double chi2 = summary.initial_chi2;
  double lambda = -1.0;  // < 0: initialise from H at the next damped iteration
  double lambda_floor = 0.0;
  double nu = 2.0;
  // kGaussNewtonFallback takes undamped steps, accepting a temporary increase of chi2
  // (non-monotone), until `fallback_patience` steps in a row fail to beat the best chi2
  // seen; then it returns to the best estimate and continues as Levenberg-Marquardt.
  const bool fallback = options_.algorithm == Algorithm::kGaussNewtonFallback;
  bool damped = options_.algorithm == Algorithm::kLevenbergMarquardt;
  double best_chi2 = chi2;
  int non_improving = 0;
  // Chord steps (the default algorithm's undamped phase only; kGaussNewton stays plain
  // Gauss-Newton): the solver holds the factorisation of the last undamped step, which
  // lowered chi2 by last_decrease.
  bool chord_ready = false;
  double last_decrease = 0.0;
  double last_rho = 0.0;  // actual / model decrease of the last undamped step
  std::vector<double> best_state;
  summary.status = TerminationStatus::kMaxIterations;

  auto failure_message = [&](const LinearSolverResult& r) {
    std::string msg = std::string("linear solver: ") + toString(r.status);
    if (!r.message.empty()) msg += ": " + r.message;
    const VertexId v = im.structure.vertexOfColumn(r.column);
    if (v >= 0) msg += " (at vertex " + std::to_string(v) + ")";
    if (!summary.unanchored.empty()) {
      msg += "; vertices without anchor start with " + std::to_string(summary.unanchored[0][0]);
    }
    return msg;
  };

  for (int it = 1; it <= options_.max_iterations; ++it) {
    IterationStats st;
    st.iteration = it;
    auto ta = Clock::now();
    im.structure.linearize();
    auto tb = Clock::now();
    st.time.linearize = seconds(ta, tb);
    im.assemble();
    auto tc = Clock::now();
    st.time.build = seconds(tb, tc);

    if (damped) {
      im.saveDiagonal();
      double max_diag = 0.0;
      for (int i = 0; i < n; ++i) max_diag = std::max(max_diag, std::abs(im.saved_diag[i]));
      if (lambda < 0) {
        const double scale =
            options_.damping == Options::Damping::kIdentity ? std::max(max_diag, 1e-12) : 1.0;
        lambda = options_.initial_lambda_factor * scale;
        // Below this the damping is lost in rounding: a lambda shrunk further by a long
        // run of good steps would need more rejections to matter again than an iteration
        // allows, and the optimizer would stop at a point that is not a minimum.
        lambda_floor = kMinRelativeLambda * scale;
        nu = 2.0;
      }
      if (options_.damping == Options::Damping::kDiagonal) {
        im.damping_diag.resize(static_cast<std::size_t>(n));
        for (int i = 0; i < n; ++i) im.damping_diag[i] = std::clamp(im.saved_diag[i], 1e-6, 1e32);
      } else {
        im.damping_diag.assign(static_cast<std::size_t>(n), 1.0);
      }
    } else if (fallback && chi2 <= best_chi2) {
      best_chi2 = chi2;
      im.saveState(best_state);
    }

    // Near convergence (or where the problem is close to linear) H hardly changes between
    // steps: conjugate gradients preconditioned with the last factorisation give a step (a
    // chord step) almost as good, for the price of a few solves. It is the iteration's step
    // when it lowers chi2 (the next iteration factorises again unless its iterations
    // reached their tolerance); otherwise it is undone and the iteration goes on as usual.
    bool chord = false;
    bool chord_converged = false;
    double chord_chi2 = chi2;
    const int chord_budget = chord_ready ? im.chordIterations() : 0;
    if (chord_ready &&
        (last_decrease < kChordTrigger * chi2 || (std::abs(1.0 - last_rho) < kChordAgreement &&
                                                  chord_budget >= kChordAgreementIterations))) {
      const auto ts = Clock::now();
      const auto [cg_iterations, cg_converged] =
          im.chordSolve(kChordRelativeTolerance,
                        kChordAbsoluteTolerance * options_.function_tolerance * chi2, chord_budget);
      st.cg_iterations = cg_iterations;
      chord_converged = cg_converged;
      if (cg_iterations > 0) {
        im.applyUpdate();
        chord_chi2 = im.evalChi2(graph_);
        chord = chord_chi2 < chi2 || (chord_chi2 == chi2 && chi2 == 0.0);
        if (!chord) im.undoUpdate();
      }
      st.time.solve += seconds(ts, Clock::now());
    }

    bool accepted = chord;
    bool stop = false;
    double new_chi2 = chord ? chord_chi2 : chi2;
    int attempts = 0;
    double used_lambda = 0.0;
    while (!chord) {
      ++attempts;
      used_lambda = damped ? lambda : 0.0;
      auto tf0 = Clock::now();
      LinearSolverResult r = im.factorize(used_lambda);
      auto tf1 = Clock::now();
      st.time.factorize += seconds(tf0, tf1);
      if (r.ok()) {
        r = im.solve();
      }
      if (!r.ok()) {
        st.time.solve += seconds(tf1, Clock::now());
        if (damped && attempts <= options_.max_rejections) {
          lambda *= nu;
          nu *= 2.0;
          continue;
        }
        summary.status = TerminationStatus::kNumericalFailure;
        summary.message = failure_message(r);
        stop = true;
        break;
      }
      im.applyUpdate();
      new_chi2 = im.evalChi2(graph_);
      st.time.solve += seconds(tf1, Clock::now());
      if (!damped && fallback && it == 1 && options_.first_step_dogleg && !im.jacobian_form &&
          !(new_chi2 <= chi2)) {
        // The first undamped step raised chi2: from the initial estimate the quadratic
        // model can be far off. A dogleg step in a trust region shrunk until the model
        // agrees, from the same factorisation (Options::first_step_dogleg).
        const auto td = Clock::now();
        im.undoUpdate();
        const Impl::DoglegResult dogleg = im.firstStepDogleg(graph_, chi2, new_chi2);
        new_chi2 = dogleg.chi2;
        st.dogleg_halvings = dogleg.halvings;
        st.dogleg_trials = dogleg.trials;
        st.time.solve += seconds(td, Clock::now());
      }
      if (!damped) {
        if (!std::isfinite(new_chi2) && !fallback) {
          im.undoUpdate();
          new_chi2 = im.evalChi2(graph_);
          summary.status = TerminationStatus::kNumericalFailure;
          summary.message = "chi2 is not finite after the update";
          stop = true;
          break;
        }
        accepted = true;
        break;
      }
      double dx2 = 0.0;
      double bdx = 0.0;
      for (int i = 0; i < n; ++i) {
        dx2 += im.dx[i] * im.dx[i] * im.damping_diag[i];
        bdx += im.structure.gradient()[i] * im.dx[i];
      }
      const double predicted = lambda * dx2 - bdx;  // model decrease of chi2
      const double rho = (chi2 - new_chi2) / predicted;
      if (std::isfinite(new_chi2) && predicted > 0 && rho > 0) {
        const double a = 2.0 * rho - 1.0;
        lambda = std::max(lambda_floor,
                          lambda * std::max(options_.min_lambda_decrease, 1.0 - a * a * a));
        nu = 2.0;
        accepted = true;
        break;
      }
      im.undoUpdate();
      if (!(predicted > options_.function_tolerance * chi2)) {
        // The model promises no meaningful decrease: we are at a minimum.
        summary.status = TerminationStatus::kConverged;
        summary.message = "no further decrease possible";
        stop = true;
        break;
      }
      if (attempts > options_.max_rejections) {
        summary.status = TerminationStatus::kNoProgress;
        summary.message = "no decreasing step after " + std::to_string(attempts) + " attempts";
        stop = true;
        break;
      }
      lambda *= nu;
      nu *= 2.0;
    }
    if (!accepted) new_chi2 = im.evalChi2(graph_);  // errors at the restored estimate

    double step = 0.0;
    double model_decrease = 0.0;  // -g.dx: the quadratic model's decrease (undamped step)
    if (accepted) {
      for (int i = 0; i < n; ++i) {
        step += im.dx[i] * im.dx[i];
        model_decrease -= im.structure.gradient()[i] * im.dx[i];
      }
      step = std::sqrt(step);
    }
    if (fallback && !damped && !stop) {
      non_improving = (std::isfinite(new_chi2) && new_chi2 < best_chi2) ? 0 : non_improving + 1;
      if (non_improving >= options_.fallback_patience || !std::isfinite(new_chi2)) {
        im.restoreState(best_state);
        new_chi2 = im.evalChi2(graph_);
        damped = true;
        lambda = -1.0;
        step = 1.0;  // not converged: the damped phase starts now
      }
    }
    st.chi2 = new_chi2;
    st.lambda = used_lambda;
    st.step_norm = step;
    st.attempts = attempts;
    st.accepted = accepted;
    st.elapsed = seconds(t_start, Clock::now());
    summary.time += st.time;
    summary.per_iteration.push_back(st);
    summary.iterations = it;
    const double old_chi2 = chi2;
    chi2 = new_chi2;
    // A chord step that did not reach its tolerance is followed by a factorisation.
    chord_ready = fallback && !damped && !im.jacobian_form && accepted &&
                  (attempts == 1 || (chord && chord_converged)) &&
                  options_.function_tolerance > 0 && new_chi2 <= old_chi2;
    last_decrease = old_chi2 - new_chi2;
    last_rho = model_decrease > 0 ? last_decrease / model_decrease : 0.0;
    // After a chord step only its agreement with the model may call for another.
    if (chord) last_decrease = std::numeric_limits<double>::infinity();
    if (options_.callback) options_.callback(st);
    if (stop) break;
    const bool small_change =
        options_.function_tolerance > 0 &&
        std::abs(old_chi2 - new_chi2) <= options_.function_tolerance * old_chi2;
    // A Gauss-Newton phase at the optimum sees chi2 jitter by rounding; above the best
    // chi2 by no more than the function tolerance counts as being there.
    const bool above_best = chi2 > best_chi2 + options_.function_tolerance * std::abs(best_chi2);
    if ((small_change || step < options_.step_tolerance) && !(fallback && !damped && above_best)) {
      summary.status = TerminationStatus::kConverged;
      break;
    }
  }
  if (fallback && !damped && !best_state.empty() && chi2 > best_chi2) {
    // The undamped phase ended above its best point: return there.
    im.restoreState(best_state);
    chi2 = im.evalChi2(graph_);
  }
  summary.final_chi2 = chi2;
  summary.factor_nonzeros = im.solver->factorNonZeros();
  // A solver that chooses its backend at analysis ("auto") names its choice (asked at the
  // end: it may take its figures from its backend's first factorisation).
  const std::string chosen = im.solver->name();
  if (chosen.rfind(options_.linear_solver, 0) == 0) summary.linear_solver = chosen;
  summary.total_time = seconds(t_start, Clock::now());
  return summary;
}

}  // namespace graphslam
