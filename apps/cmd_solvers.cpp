// SPDX-License-Identifier: MIT
// graphslam solvers: every linear solver and ordering on one graph's linear system.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "cli_common.h"
#include "graphslam/core/error.h"
#include "graphslam/core/file_util.h"
#include "graphslam/core/linear_system.h"
#include "graphslam/core/logging.h"
#include "graphslam/core/optimizer.h"
#include "input.h"
#include "plotting.h"

namespace graphslam::apps {

namespace {

constexpr const char* kSolversUsage =
    "usage: graphslam solvers INPUT [--solvers LIST|all] [--repeats N] [--at auto|optimum|input]\n"
    "                         [--init auto|global|none] [--plot DIR] [--csv FILE] [--slow-max N]\n"
    "                         [--plugin LIB]...\n"
    "Solves the linear system of INPUT (.g2o or .npz) with every linear solver and ordering (or\n"
    "those in LIST: names, or name:ordering, comma separated) and prints, per solver and\n"
    "ordering, the median analyse / factorise / solve times of N runs (and of one step of\n"
    "iterative refinement, not in the total), the factor's non-zeros, the relative residual\n"
    "|H dx + g| / |g| and the largest difference to a reference solution (SuiteSparseQR on J,\n"
    "else Eigen LDL^T), after refinement and without it. The fastest solver named is the\n"
    "fastest whose solution without refinement is within 1e-8 of the reference. The system\n"
    "is taken at the optimum (after the initial guess of --init and optimising with\n"
    "--algorithm, at most -i iterations; as graphslam optimize does) or at the input's\n"
    "estimates; auto: the input's for .npz homework files (their initial guess, so dx is the\n"
    "whole solution of a linear problem), the optimum for .g2o. With ground truth (.npz) the\n"
    "reference solution's position errors are printed. --plot DIR writes PNG pictures of the\n"
    "sparsity of H, J and every factor, and of the solution against the ground truth.\n"
    "The homework's nonlinear study (the system of the 10th Gauss-Newton step):\n"
    "  graphslam solvers 2d_nonlinear.npz --at optimum --algorithm gn -i 9";

using Clock = std::chrono::steady_clock;

/// Largest difference to the reference solution the study accepts (max abs): the "fastest"
/// solver must reach it with its own solve, without refinement.
constexpr double kAgreement = 1e-8;

double since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

/// The linear system of a graph at its current estimates, copied out of LinearSystem.
struct StudySystem {
  int n = 0;
  // H (upper, full diagonal blocks) and g.
  std::vector<int> h_ptr, h_idx, block_starts;
  std::vector<double> h_values, gradient;
  // Whitened J and r (with the damping rows, zero).
  JacobianStructure j;
  std::vector<int> j_ptr, j_idx;
  std::vector<double> j_values, residual;
  int num_blocks = 0;

  SparseStructure hessian() const {
    SparseStructure s;
    s.n = n;
    s.col_ptr = h_ptr.data();
    s.row_idx = h_idx.data();
    s.block_starts = block_starts.data();
    s.num_blocks = num_blocks;
    return s;
  }
  JacobianStructure jacobian() const {
    JacobianStructure s = j;
    s.col_ptr = j_ptr.data();
    s.row_idx = j_idx.data();
    s.block_starts = block_starts.data();
    return s;
  }
  std::size_t jacobianNonZeros() const {  // without the damping rows
    std::size_t nnz = 0;
    for (int r : j_idx) nnz += r < j.damping_row ? 1u : 0u;
    return nnz;
  }
  /// y += H x (from the upper triangle).
  void multiplyAdd(const std::vector<double>& x, std::vector<double>& y) const {
    for (int c = 0; c < n; ++c) {
      for (int k = h_ptr[c]; k < h_ptr[c + 1]; ++k) {
        const int r = h_idx[k];
        if (r > c) continue;
        y[r] += h_values[k] * x[c];
        if (r != c) y[c] += h_values[k] * x[r];
      }
    }
  }
  /// y = J^T (J x + r): the gradient at x computed from J itself, which is more accurate
  /// than H x + g when H is ill-conditioned (corrected semi-normal equations).
  void gradientFromJacobian(const std::vector<double>& x, std::vector<double>& y) const {
    std::vector<double> jr(residual);  // J x + r, over all rows
    for (int c = 0; c < n; ++c) {
      for (int k = j_ptr[c]; k < j_ptr[c + 1]; ++k) jr[j_idx[k]] += j_values[k] * x[c];
    }
    y.assign(static_cast<std::size_t>(n), 0.0);
    for (int c = 0; c < n; ++c) {
      double acc = 0.0;
      for (int k = j_ptr[c]; k < j_ptr[c + 1]; ++k) acc += j_values[k] * jr[j_idx[k]];
      y[c] = acc;
    }
  }
  /// |H x + g| / |g|.
  double relativeResidual(const std::vector<double>& x) const {
    std::vector<double> y(gradient);
    multiplyAdd(x, y);
    double num = 0.0, den = 0.0;
    for (int i = 0; i < n; ++i) {
      num += y[i] * y[i];
      den += gradient[i] * gradient[i];
    }
    return den > 0 ? std::sqrt(num / den) : std::sqrt(num);
  }
};

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
  return s;
}

struct Row {
  std::string solver, ordering, form;
  double analyze = 0, factorize = 0, solve = 0;
  double refine = 0;  // iterative refinement after the solve (not in total())
  std::size_t factor_nnz = 0;
  double residual = NAN, max_diff = NAN, max_diff_unrefined = NAN;
  std::string status = "ok";
  std::vector<double> x, x_unrefined;
  std::vector<int> factor_ptr, factor_idx;  // for pictures
  [[nodiscard]] double total() const { return analyze + factorize + solve; }
  [[nodiscard]] bool ok() const { return status == "ok"; }
};

/// Runs one solver spec `repeats` times on fresh instances; the last run's solution.
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

/// Writes a sparsity pattern for tools/plot/plot_spy.py: a header line
/// `rows,cols,nnz,title`, then `r,c,count` per occupied cell of a grid of at most
/// 1000 x 1000 cells (the tool bins large matrices itself).
void writePattern(const std::string& path, int rows, int cols, const std::vector<int>& ptr,
                  const std::vector<int>& idx, const std::string& title, bool upper_only) {
  const int grid = 1000;
  const double sr = rows > grid ? static_cast<double>(grid) / rows : 1.0;
  const double sc = cols > grid ? static_cast<double>(grid) / cols : 1.0;
  std::map<std::pair<int, int>, int> cells;
  std::size_t nnz = 0;
  for (int c = 0; c + 1 < static_cast<int>(ptr.size()); ++c) {
    for (int k = ptr[c]; k < ptr[c + 1]; ++k) {
      const int r = idx[k];
      if (upper_only && r > c) continue;
      ++nnz;
      ++cells[{static_cast<int>(r * sr), static_cast<int>(c * sc)}];
    }
  }
  writeFileAtomically(path, [&](std::ostream& out) {
    out << rows << ',' << cols << ',' << nnz << ',' << std::min(rows, grid) << ','
        << std::min(cols, grid) << ',' << title << '\n';
    for (const auto& [rc, count] : cells)
      out << rc.first << ',' << rc.second << ',' << count << '\n';
  });
}

std::string fmtTime(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", s);
  return buf;
}

}  // namespace

int cmdSolvers(const std::vector<std::string>& args) {
  std::string input, list, plot_dir, csv, at, algorithm, init;
  int repeats = 3, slow_max = 3000, iterations = 100, qr_max_nnz = 100000, refine = 1;
  std::vector<std::string> plugins;
  po::options_description desc("options");
  desc.add_options()("help,h", "show this help")("input", po::value(&input), "input .g2o file")(
      "solvers", po::value(&list)->default_value("all"),
      "comma-separated solver names (all their orderings) or name:ordering, or all")(
      "repeats", po::value(&repeats)->default_value(3), "runs per solver (medians reported)")(
      "at", po::value(&at)->default_value("auto"),
      "linearise at the optimum (optimise first), at the input's estimates, or auto")(
      "algorithm", po::value(&algorithm)->default_value("auto"),
      "optimiser for --at optimum: auto, gn or lm")(
      "init", po::value(&init)->default_value("auto"),
      "initial guess for --at optimum, as in graphslam optimize: auto (global for .g2o, the "
      "homework's for .npz), global or none (the file's estimates)")(
      "iterations,i", po::value(&iterations)->default_value(100),
      "maximum iterations for --at optimum")("plot", po::value(&plot_dir),
                                             "write sparsity pictures (PNG) into this directory")(
      "csv", po::value(&csv), "write the table as CSV")(
      "slow-max", po::value(&slow_max)->default_value(3000),
      "skip dense-ldlt, dense-pinv and eigen-qr above this many unknowns (0: never skip)")(
      "refine", po::value(&refine)->default_value(1),
      "steps of iterative refinement for the normal-equation solvers, x -= H^-1 J^T (J x + r) "
      "(the gradient from J, not H: corrected semi-normal equations), timed in its own column "
      "and not in the total; QR on J needs none")(
      "eigen-qr-max-nnz", po::value(&qr_max_nnz)->default_value(100000),
      "skip eigen-qr when J has more non-zeros (0: never skip)")(
      "plugin", po::value(&plugins)->composing(), "load solvers/types from this library");
  po::positional_options_description pos;
  pos.add("input", 1);
  const auto vm = parse(args, desc, &pos);
  if (vm.count("help")) {
    printHelp(kSolversUsage, desc);
    return kExitOk;
  }
  if (input.empty()) throw UsageError("solvers needs an INPUT file");
  if (repeats < 1) throw UsageError("--repeats must be at least 1");
  if (refine < 0) throw UsageError("--refine must be at least 0");
  if (at != "optimum" && at != "input" && at != "auto") {
    throw UsageError("--at must be auto, optimum or input");
  }
  if (iterations < 1) throw UsageError("--iterations must be at least 1");
  checkInitChoice(init);
  Registries reg;
  loadRegistries(reg, plugins);

  // The (solver, ordering) pairs to run.
  std::vector<std::pair<std::string, Ordering>> specs;
  auto add_all_orderings = [&](const SolverRegistry::Entry& e) {
    for (Ordering o : e.orderings) specs.emplace_back(e.name, o);
  };
  if (list == "all") {
    for (const auto* e : reg.solvers.entries()) add_all_orderings(*e);
  } else {
    std::stringstream ss(list);
    std::string item;
    while (std::getline(ss, item, ',')) {
      if (item.empty()) continue;
      if (!reg.solvers.contains(item)) {
        throw UsageError("unknown solver or ordering '" + item +
                         "' (graphslam list-solvers shows the known ones)");
      }
      const auto colon = item.find(':');
      const auto* e = reg.solvers.find(item.substr(0, colon));
      if (colon == std::string::npos) {
        add_all_orderings(*e);
      } else {
        Ordering o;
        (void)parseOrdering(item.substr(colon + 1), o);
        specs.emplace_back(e->name, o == Ordering::kDefault ? e->orderings.front() : o);
      }
    }
  }
  if (specs.empty()) throw UsageError("--solvers lists no solver");

  LoadedInput in = loadInput(input, reg.types);
  Graph& graph = in.graph;
  std::cout << in.description << "\n";
  for (const auto& note : in.notes) std::cout << note << "\n";
  if (at == "auto") at = in.keep_initial_guess ? "input" : "optimum";
  std::cout << "linearised at the " << (at == "input" ? "input's estimates" : "optimum") << "\n";
  if (at == "optimum") {
    applyInitialGuess(in, graph, init, reg.solvers);
    Optimizer::Options options;
    options.max_iterations = iterations;
    if (algorithm == "gn") {
      options.algorithm = Algorithm::kGaussNewton;
    } else if (algorithm == "lm") {
      options.algorithm = Algorithm::kLevenbergMarquardt;
    } else if (algorithm != "auto") {
      throw UsageError("--algorithm must be auto, gn or lm");
    }
    Optimizer optimizer(graph, reg.solvers, options);
    const Summary summary = optimizer.optimize();
    std::printf("optimised first (%s): chi2 %.10g -> %.10g in %d iterations (%s)\n",
                toString(options.algorithm), summary.initial_chi2, summary.final_chi2,
                summary.iterations, toString(summary.status));
    if (!summary.succeeded()) {
      std::cerr << "optimisation failed: " << summary.message << "\n";
      return kExitFailed;
    }
  }
  if (Vertex* v = fixGaugeIfFree(graph)) {
    std::cout << "no vertex is fixed and no prior exists: fixing vertex " << v->id()
              << " for the study\n";
  }
  const StudySystem sys = linearSystemOf(graph);
  if (sys.n == 0) throw Error(input + ": no free vertex with an edge: there is no system to solve");
  std::printf(
      "system: %d unknowns, H %zu stored non-zeros (upper, full diagonal blocks), J %d x %d "
      "with %zu non-zeros, chi2 %.10g\n",
      sys.n, sys.h_idx.size(), sys.j.damping_row, sys.n, sys.jacobianNonZeros(), graph.chi2());

  // Reference solution.
  std::vector<double> reference;
  std::string reference_name;
  for (const char* ref : {"spqr", "eigen-ldlt"}) {
    if (!reg.solvers.contains(ref)) continue;
    const auto* e = reg.solvers.find(ref);
    Row r = runSolver(reg.solvers, ref, e->orderings.front(), sys, 1, false, refine);
    if (r.ok()) {
      reference = r.x;
      reference_name = std::string(ref) + ":" + toString(e->orderings.front());
      break;
    }
  }
  if (reference.empty()) {
    std::cerr << "no reference solution: the system is singular or indefinite\n";
  }

  const bool want_pattern = !plot_dir.empty();
  std::vector<Row> rows;
  for (const auto& [name, ordering] : specs) {
    const bool slow = name == "dense-ldlt" || name == "dense-pinv" || name == "eigen-qr";
    std::string skip;
    if (slow && slow_max > 0 && sys.n > slow_max) {
      skip = std::to_string(sys.n) + " unknowns > --slow-max " + std::to_string(slow_max) +
             (name == "eigen-qr" ? " (Eigen's SparseQR fills R far beyond SPQR's)"
                                 : " (dense, O(n^3) time and n^2 memory)");
    } else if (name == "eigen-qr" && qr_max_nnz > 0 &&
               sys.jacobianNonZeros() > static_cast<std::size_t>(qr_max_nnz)) {
      skip = "J has " + std::to_string(sys.jacobianNonZeros()) +
             " non-zeros > --eigen-qr-max-nnz " + std::to_string(qr_max_nnz) +
             " (Eigen's SparseQR takes minutes there)";
    }
    if (!skip.empty()) {
      Row row;
      row.solver = name;
      row.ordering = toString(ordering);
      row.form = reg.solvers.find(name)->form == SystemForm::kJacobian ? "J" : "H";
      row.status = "skipped: " + skip;
      rows.push_back(std::move(row));
      continue;
    }
    std::cerr << "running " << name << ":" << toString(ordering) << " ...\n";
    Row row = runSolver(reg.solvers, name, ordering, sys, repeats, want_pattern, refine);
    if (row.ok() && !reference.empty()) {
      auto max_diff = [&](const std::vector<double>& x) {
        double m = 0.0;
        for (int i = 0; i < sys.n; ++i) m = std::max(m, std::abs(x[i] - reference[i]));
        return m;
      };
      row.max_diff = max_diff(row.x);
      row.max_diff_unrefined = max_diff(row.x_unrefined);
    }
    rows.push_back(std::move(row));
  }

  // Table.
  // total = analyse + factorise + solve; "refine s" and the residual and max|diff| after
  // it are extra (the solve alone is what SciPy's spsolve does); "unrefined" is max|diff|
  // of the solve alone.
  std::printf("\n%-19s %-8s %-4s %10s %10s %10s %10s %10s %12s %10s %10s %10s  %s\n", "solver",
              "ordering", "form", "analyse s", "factor s", "solve s", "total s", "refine s",
              "nnz(factor)", "residual", "max|diff|", "unrefined", "status");
  for (const Row& r : rows) {
    if (r.ok()) {
      std::printf(
          "%-19s %-8s %-4s %10.4g %10.4g %10.4g %10.4g %10.4g %12zu %10.2e %10.2e %10.2e  ok\n",
          r.solver.c_str(), r.ordering.c_str(), r.form.c_str(), r.analyze, r.factorize, r.solve,
          r.total(), r.refine, r.factor_nnz, r.residual, r.max_diff, r.max_diff_unrefined);
    } else {
      std::printf("%-19s %-8s %-4s %10s %10s %10s %10s %10s %12s %10s %10s %10s  %s\n",
                  r.solver.c_str(), r.ordering.c_str(), r.form.c_str(), "-", "-", "-", "-", "-",
                  "-", "-", "-", "-", r.status.c_str());
    }
  }
  // The fastest solver whose own solution (without refinement) agrees with the reference.
  const Row* fastest = nullptr;
  for (const Row& r : rows) {
    const bool agrees = reference.empty() || r.max_diff_unrefined <= kAgreement;
    if (r.ok() && agrees && (!fastest || r.total() < fastest->total())) fastest = &r;
  }
  if (fastest) {
    std::printf(
        "\nfastest: %s:%s, %s s (median of %d; analyse + factorise + solve, its solution within "
        "%g of the reference without refinement); reference %s\n",
        fastest->solver.c_str(), fastest->ordering.c_str(), fmtTime(fastest->total()).c_str(),
        repeats, kAgreement, reference_name.empty() ? "none" : reference_name.c_str());
  }

  // The reference solution against the ground truth.
  const auto initial_positions = positions(graph);
  const auto before = homework::positionErrors(graph, in.ground_truth);
  if (!reference.empty() && !in.ground_truth.empty()) {
    for (Vertex* v : [&] {
           std::vector<Vertex*> vs;
           for (const auto& [id, vp] : graph.vertices()) {
             if (vp->hessianIndex() >= 0) vs.push_back(vp.get());
           }
           return vs;
         }()) {
      v->oplus(reference.data() + v->hessianIndex());
    }
    const auto after = homework::positionErrors(graph, in.ground_truth);
    std::printf(
        "position error vs ground truth (m) of the estimate, before -> after the reference "
        "step:\n");
    printErrors("poses", before.poses, after.poses);
    printErrors("landmarks", before.landmarks, after.landmarks);
  }

  if (!csv.empty()) {
    writeFileAtomically(csv, [&](std::ostream& out) {
      out.precision(10);
      out << "solver,ordering,form,n,nnz_matrix,analyze_s,factorize_s,solve_s,total_s,factor_nnz,"
             "residual,max_diff,status,refine_s,max_diff_unrefined\n";
      for (const Row& r : rows) {
        const std::size_t nnz_matrix = r.form == "J" ? sys.jacobianNonZeros() : sys.h_idx.size();
        std::string status = r.ok() ? "ok" : r.status;
        std::replace(status.begin(), status.end(), ',', ';');
        out << r.solver << ',' << r.ordering << ',' << r.form << ',' << sys.n << ',' << nnz_matrix
            << ',' << r.analyze << ',' << r.factorize << ',' << r.solve << ',' << r.total() << ','
            << r.factor_nnz << ',' << r.residual << ',' << r.max_diff << ',' << status << ','
            << r.refine << ',' << r.max_diff_unrefined << '\n';
      }
    });
    std::cout << "wrote " << csv << "\n";
  }

  if (!plot_dir.empty()) {
    namespace fs = std::filesystem;
    fs::create_directories(fs::path(plot_dir) / "data");
    std::vector<std::string> plot_args{plot_dir};
    const std::string stem = fs::path(input).stem().string();
    auto add = [&](const std::string& name, int r, int c, const std::vector<int>& ptr,
                   const std::vector<int>& idx, const std::string& title, bool upper) {
      const std::string path = (fs::path(plot_dir) / "data" / (name + ".csv")).string();
      writePattern(path, r, c, ptr, idx, title, upper);
      plot_args.push_back(path);
    };
    add(stem + "_H", sys.n, sys.n, sys.h_ptr, sys.h_idx, stem + ": H (upper triangle)", true);
    {
      // J without its damping rows.
      std::vector<int> ptr(1, 0), idx;
      for (int c = 0; c < sys.n; ++c) {
        for (int k = sys.j_ptr[c]; k < sys.j_ptr[c + 1]; ++k) {
          if (sys.j_idx[k] < sys.j.damping_row) idx.push_back(sys.j_idx[k]);
        }
        ptr.push_back(static_cast<int>(idx.size()));
      }
      add(stem + "_J", sys.j.damping_row, sys.n, ptr, idx, stem + ": whitened Jacobian J", false);
    }
    for (const Row& r : rows) {
      if (!r.ok() || r.factor_ptr.empty()) continue;
      const int cols = static_cast<int>(r.factor_ptr.size()) - 1;
      int nrows = cols;
      for (int v : r.factor_idx) nrows = std::max(nrows, v + 1);
      add(stem + "_" + r.solver + "_" + r.ordering, nrows, cols, r.factor_ptr, r.factor_idx,
          stem + ": factor of " + r.solver + ", " + r.ordering + " ordering", false);
    }
    runPlotScript("plot_spy.py", plot_args);
    std::cout << "wrote " << plot_args.size() - 1 << " pictures into " << plot_dir << "\n";
    if (!reference.empty() && !in.ground_truth.empty()) {
      plotPoints((fs::path(plot_dir) / (stem + "_estimate.png")).string(),
                 stem + ": before and after the reference step (" + reference_name + ")", graph,
                 initial_positions, in.ground_truth);
    }
  }
  return kExitOk;
}

}  // namespace graphslam::apps
