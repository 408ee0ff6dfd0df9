// SPDX-License-Identifier: MIT
// graphslam solvers: every linear solver and ordering on one graph's linear system.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>

#include "cli_common.h"
#include "graphslam/optimizer/linear_system.h"
#include "graphslam/optimizer/optimizer.h"
#include "graphslam/support/error.h"
#include "graphslam/support/file_util.h"
#include "graphslam/support/logging.h"
#include "input.h"
#include "output_set.h"
#include "plotting.h"
#include "solver_study.h"

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

/// Largest difference to the reference solution the study accepts (max abs): the "fastest"
/// solver must reach it with its own solve, without refinement.
constexpr double kAgreement = 1e-8;

/// Writes a sparsity pattern for tools/plot/plot_spy.py: a header line
/// `rows,cols,nnz,title`, then `r,c,count` per occupied cell of a grid of at most
/// 1000 x 1000 cells (the tool bins large matrices itself). `reported_nnz` (0: none) is the
/// solver table's nnz(factor): when the pattern drawn has another count (UMFPACK exports U
/// but counts L and U, SPQR counts R's stored entries) the title gives both.
void writePattern(const std::string& path, int rows, int cols, const std::vector<int>& ptr,
                  const std::vector<int>& idx, std::string title, bool upper_only,
                  std::size_t reported_nnz = 0) {
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
  if (reported_nnz != 0 && reported_nnz != nnz) {
    title += " (the table's nnz(factor): " + std::to_string(reported_nnz) + ")";
  }
  support::writeFileAtomically(path, [&](std::ostream& out) {
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

struct SolversOptions {
  std::string input, list, plot_dir, csv, at, algorithm, init;
  int repeats = 3, slow_max = 3000, iterations = 100, qr_max_nnz = 100000, refine = 1;
  std::vector<std::string> plugins;
};

void declareOptions(po::options_description& desc, SolversOptions& o) {
  desc.add_options()("help,h", "show this help")("input", po::value(&o.input), "input .g2o file")(
      "solvers", po::value(&o.list)->default_value("all"),
      "comma-separated solver names (all their orderings) or name:ordering, or all")(
      "repeats", po::value(&o.repeats)->default_value(3), "runs per solver (medians reported)")(
      "at", po::value(&o.at)->default_value("auto"),
      "linearise at the optimum (optimise first), at the input's estimates, or auto")(
      "algorithm", po::value(&o.algorithm)->default_value("auto"),
      "optimiser for --at optimum: auto, gn or lm")(
      "init", po::value(&o.init)->default_value("auto"),
      "initial guess for --at optimum, as in graphslam optimize: auto (global for .g2o, the "
      "homework's for .npz), global or none (the file's estimates)")(
      "iterations,i", po::value(&o.iterations)->default_value(100),
      "maximum iterations for --at optimum")("plot", po::value(&o.plot_dir),
                                             "write sparsity pictures (PNG) into this directory")(
      "csv", po::value(&o.csv), "write the table as CSV")(
      "slow-max", po::value(&o.slow_max)->default_value(3000),
      "skip dense-ldlt, dense-pinv, eigen-qr and the natural orderings above this many "
      "unknowns (0: never skip)")(
      "refine", po::value(&o.refine)->default_value(1),
      "steps of iterative refinement for the normal-equation solvers, x -= H^-1 J^T (J x + r) "
      "(the gradient from J, not H: corrected semi-normal equations), timed in its own column "
      "and not in the total; QR on J needs none")(
      "eigen-qr-max-nnz", po::value(&o.qr_max_nnz)->default_value(100000),
      "skip eigen-qr when J has more non-zeros (0: never skip)")(
      "plugin", po::value(&o.plugins)->composing(), "load solvers/types from this library");
}

/// Parses and checks the options; false after --help.
bool parseOptions(const std::vector<std::string>& args, SolversOptions& o) {
  po::options_description desc("options");
  declareOptions(desc, o);
  po::positional_options_description pos;
  pos.add("input", 1);
  const auto vm = parse(args, desc, &pos);
  if (vm.count("help")) {
    printHelp(kSolversUsage, desc);
    return false;
  }
  if (o.input.empty()) throw UsageError("solvers needs an INPUT file");
  if (o.repeats < 1) throw UsageError("--repeats must be at least 1");
  if (o.refine < 0) throw UsageError("--refine must be at least 0");
  if (o.at != "optimum" && o.at != "input" && o.at != "auto") {
    throw UsageError("--at must be auto, optimum or input");
  }
  if (o.iterations < 1) throw UsageError("--iterations must be at least 1");
  checkInitChoice(o.init);
  return true;
}

using Spec = std::pair<std::string, Ordering>;

/// The (solver, ordering) pairs of --solvers.
std::vector<Spec> solverSpecs(const std::string& list, const SolverRegistry& solvers) {
  std::vector<Spec> specs;
  auto add_all_orderings = [&](const SolverRegistry::Entry& e) {
    for (Ordering o : e.orderings) specs.emplace_back(e.name, o);
  };
  if (list == "all") {
    for (const auto* e : solvers.entries()) add_all_orderings(*e);
  } else {
    std::stringstream ss(list);
    std::string item;
    while (std::getline(ss, item, ',')) {
      if (item.empty()) continue;
      if (!solvers.contains(item)) {
        throw UsageError("unknown solver or ordering '" + item +
                         "' (graphslam list-solvers shows the known ones)");
      }
      const auto colon = item.find(':');
      const auto* e = solvers.find(item.substr(0, colon));
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
  return specs;
}

/// Optimises the graph from the initial guess of --init, as graphslam optimize does;
/// false (after saying why) when the optimisation fails.
bool optimiseFirst(const SolversOptions& o, LoadedInput& in, const SolverRegistry& solvers) {
  Graph& graph = in.graph;
  applyInitialGuess(in, graph, o.init, solvers);
  Optimizer::Options options;
  options.max_iterations = o.iterations;
  options.algorithm = parseAlgorithm(o.algorithm);
  Optimizer optimizer(graph, solvers, options);
  const Summary summary = optimizer.optimize();
  std::printf("optimised first (%s): chi2 %.10g -> %.10g in %d iterations (%s)\n",
              toString(options.algorithm), summary.initial_chi2, summary.final_chi2,
              summary.iterations, toString(summary.status));
  if (!summary.succeeded()) {
    std::cerr << "optimisation failed: " << summary.message << "\n";
    return false;
  }
  return true;
}

/// The solution the others are compared with: SuiteSparseQR on J, else Eigen's LDL^T.
struct Reference {
  std::vector<double> x;
  std::string name;
};

Reference referenceSolution(const SolverRegistry& solvers, const StudySystem& sys, int refine) {
  Reference reference;
  for (const char* ref : {"spqr", "eigen-ldlt"}) {
    if (!solvers.contains(ref)) continue;
    const auto* e = solvers.find(ref);
    Row r = runSolver(solvers, ref, e->orderings.front(), sys, 1, false, refine);
    if (r.ok()) {
      reference.x = r.x;
      reference.name = std::string(ref) + ":" + toString(e->orderings.front());
      break;
    }
  }
  if (reference.x.empty()) {
    std::cerr << "no reference solution: the system is singular or indefinite\n";
  }
  return reference;
}

/// Why solver `name` with `ordering` is not run on this system (--slow-max,
/// --eigen-qr-max-nnz); empty if it is.
std::string skipReason(const std::string& name, Ordering ordering, const StudySystem& sys,
                       const SolversOptions& o) {
  const bool slow = name == "dense-ldlt" || name == "dense-pinv" || name == "eigen-qr";
  if (slow && o.slow_max > 0 && sys.n > o.slow_max) {
    return std::to_string(sys.n) + " unknowns > --slow-max " + std::to_string(o.slow_max) +
           (name == "eigen-qr" ? " (Eigen's SparseQR fills R far beyond SPQR's)"
                               : " (dense, O(n^3) time and n^2 memory)");
  }
  if (o.slow_max > 0 && sys.n > o.slow_max && ordering == Ordering::kNatural) {
    return std::to_string(sys.n) + " unknowns > --slow-max " + std::to_string(o.slow_max) +
           " (without a fill-reducing ordering the factor of a large graph fills in: minutes "
           "and gigabytes)";
  }
  if (name == "eigen-qr" && o.qr_max_nnz > 0 &&
      sys.jacobianNonZeros() > static_cast<std::size_t>(o.qr_max_nnz)) {
    return "J has " + std::to_string(sys.jacobianNonZeros()) + " non-zeros > --eigen-qr-max-nnz " +
           std::to_string(o.qr_max_nnz) + " (Eigen's SparseQR takes minutes there)";
  }
  return {};
}

/// Runs every spec (or marks it skipped) and compares its solutions with the reference.
std::vector<Row> runAll(const std::vector<Spec>& specs, const SolverRegistry& solvers,
                        const StudySystem& sys, const Reference& reference,
                        const SolversOptions& o) {
  const bool want_pattern = !o.plot_dir.empty();
  std::vector<Row> rows;
  for (const auto& [name, ordering] : specs) {
    const std::string skip = skipReason(name, ordering, sys, o);
    if (!skip.empty()) {
      Row row;
      row.solver = name;
      row.ordering = toString(ordering);
      row.form = solvers.find(name)->form == SystemForm::kJacobian ? "J" : "H";
      row.status = "skipped: " + skip;
      rows.push_back(std::move(row));
      continue;
    }
    std::cerr << "running " << name << ":" << toString(ordering) << " ...\n";
    Row row = runSolver(solvers, name, ordering, sys, o.repeats, want_pattern, o.refine);
    if (row.ok() && !reference.x.empty()) {
      auto max_diff = [&](const std::vector<double>& x) {
        double m = 0.0;
        for (int i = 0; i < sys.n; ++i) m = std::max(m, std::abs(x[i] - reference.x[i]));
        return m;
      };
      row.max_diff = max_diff(row.x);
      row.max_diff_unrefined = max_diff(row.x_unrefined);
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

/// The table, then the fastest solver whose own solution (without refinement) agrees with
/// the reference.
void printTable(const std::vector<Row>& rows, const Reference& reference, int repeats) {
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
  const Row* fastest = nullptr;
  for (const Row& r : rows) {
    const bool agrees = reference.x.empty() || r.max_diff_unrefined <= kAgreement;
    if (r.ok() && agrees && (!fastest || r.total() < fastest->total())) fastest = &r;
  }
  if (fastest) {
    std::printf(
        "\nfastest: %s:%s, %s s (median of %d; analyse + factorise + solve, its solution within "
        "%g of the reference without refinement); reference %s\n",
        fastest->solver.c_str(), fastest->ordering.c_str(), fmtTime(fastest->total()).c_str(),
        repeats, kAgreement, reference.name.empty() ? "none" : reference.name.c_str());
  }
}

/// Applies the reference step to the graph and prints the position errors against the
/// ground truth before and after it.
void applyReferenceStep(Graph& graph, const io::PointGroundTruth& truth, const StudySystem& sys,
                        const std::vector<double>& reference) {
  const auto before = eval::positionErrors(graph, truth);
  for (const auto& [v, column] : sys.columns) v->oplus(reference.data() + column);
  const auto after = eval::positionErrors(graph, truth);
  std::printf(
      "position error vs ground truth (m) of the estimate, before -> after the reference "
      "step:\n");
  printErrors("poses", before.poses, after.poses);
  printErrors("landmarks", before.landmarks, after.landmarks);
}

/// The table as CSV into `outputs`' staged file for `csv`, put in place.
void writeCsv(const std::string& csv, OutputSet& outputs, const std::vector<Row>& rows,
              const StudySystem& sys) {
  support::writeFileAtomically(outputs.staged(csv), [&](std::ostream& out) {
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
  outputs.commit();
  std::cout << "wrote " << csv << "\n";
}

/// Writes the sparsity patterns of H, J and every factor into DIR/data and draws them into
/// DIR; returns how many pictures.
std::size_t plotPatterns(const std::string& plot_dir, const std::string& stem,
                         const StudySystem& sys, const std::vector<Row>& rows) {
  namespace fs = std::filesystem;
  fs::create_directories(fs::path(plot_dir) / "data");
  std::vector<std::string> plot_args{plot_dir};
  auto add = [&](const std::string& name, int r, int c, const std::vector<int>& ptr,
                 const std::vector<int>& idx, const std::string& title, bool upper,
                 std::size_t reported_nnz = 0) {
    const std::string path = (fs::path(plot_dir) / "data" / (name + ".csv")).string();
    writePattern(path, r, c, ptr, idx, title, upper, reported_nnz);
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
        stem + ": factor of " + r.solver + ", " + r.ordering + " ordering", false, r.factor_nnz);
  }
  runPlotScript("plot_spy.py", plot_args);
  return plot_args.size() - 1;
}

/// Loads the input and linearises it where --at says (optimising first at the optimum);
/// false when that optimisation fails.
bool prepareGraph(SolversOptions& o, LoadedInput& in, const SolverRegistry& solvers) {
  std::cout << in.description << "\n";
  for (const auto& note : in.notes) std::cout << note << "\n";
  if (o.at == "auto") o.at = in.keep_initial_guess ? "input" : "optimum";
  std::cout << "linearised at the " << (o.at == "input" ? "input's estimates" : "optimum") << "\n";
  if (o.at == "optimum" && !optimiseFirst(o, in, solvers)) return false;
  if (Vertex* v = fixGaugeIfFree(in.graph)) {
    std::cout << "no vertex is fixed and no prior exists: fixing vertex " << v->id()
              << " for the study\n";
  }
  return true;
}

void printSystem(const StudySystem& sys, Graph& graph) {
  std::printf(
      "system: %d unknowns, H %zu stored non-zeros (upper, full diagonal blocks), J %d x %d "
      "with %zu non-zeros, chi2 %.10g\n",
      sys.n, sys.h_idx.size(), sys.j.damping_row, sys.n, sys.jacobianNonZeros(), graph.chi2());
}

}  // namespace

int cmdSolvers(const std::vector<std::string>& args) {
  SolversOptions o;
  if (!parseOptions(args, o)) return kExitOk;
  Registries reg;
  loadRegistries(reg, o.plugins);
  const std::vector<Spec> specs = solverSpecs(o.list, reg.solvers);
  // The CSV's folder is checked (and the picture folder created) before the study, which
  // can take minutes; the pictures are staged and put in place together.
  OutputSet outputs({o.csv}, {o.input});
  std::optional<OutputFolder> pictures;
  if (!o.plot_dir.empty()) pictures.emplace(o.plot_dir);

  LoadedInput in = loadInput(o.input, reg);
  Graph& graph = in.graph;
  if (!prepareGraph(o, in, reg.solvers)) return kExitFailed;
  const StudySystem sys = linearSystemOf(graph);
  if (sys.n == 0) {
    throw Error(o.input + ": no free vertex with an edge: there is no system to solve");
  }
  printSystem(sys, graph);

  const Reference reference = referenceSolution(reg.solvers, sys, o.refine);
  const std::vector<Row> rows = runAll(specs, reg.solvers, sys, reference, o);
  printTable(rows, reference, o.repeats);

  const bool with_truth = !reference.x.empty() && !in.ground_truth.empty();
  const auto initial_positions = positions(graph);
  if (with_truth) applyReferenceStep(graph, in.ground_truth, sys, reference.x);
  if (!o.csv.empty()) writeCsv(o.csv, outputs, rows, sys);
  if (pictures) {
    const std::string stem = std::filesystem::path(o.input).stem().string();
    const std::size_t count = plotPatterns(pictures->staged(), stem, sys, rows);
    if (with_truth) {
      const std::string png = stem + "_estimate.png";
      plotPoints((std::filesystem::path(pictures->staged()) / png).string(),
                 stem + ": before and after the reference step (" + reference.name + ")", graph,
                 initial_positions, in.ground_truth,
                 (std::filesystem::path(o.plot_dir) / png).string(),
                 "before the reference step|after it");
    }
    pictures->commit();
    std::cout << "wrote " << count << " sparsity pictures"
              << (with_truth ? " and the estimate" : "") << " into " << o.plot_dir << "\n";
  }
  return kExitOk;
}

}  // namespace graphslam::apps
