// SPDX-License-Identifier: MIT
// The graphslam command-line tool: subcommands over the library. No library logic here.
#include <boost/program_options.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "builtins.h"
#include "certify_cli.h"
#include "cli_common.h"
#include "commands.h"
#include "graphslam/core/plugin.h"
#include "graphslam/eval/point_errors.h"
#include "graphslam/init/global_se2.h"
#include "graphslam/io/g2o.h"
#include "graphslam/optimizer/marginals.h"
#include "graphslam/optimizer/optimizer.h"
#include "graphslam/simulation/simulator.h"
#include "graphslam/support/error.h"
#include "graphslam/support/file_util.h"
#include "graphslam/support/logging.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"
#include "input.h"
#include "objective_options.h"
#include "observability_check.h"
#include "outlier_options.h"
#include "output_set.h"
#include "plotting.h"
#include "robust_options.h"
#include "submap_run.h"
#include "view_output.h"

#ifdef __GLIBC__
#include <malloc.h>
#endif

using namespace graphslam;
using namespace graphslam::apps;

namespace {

// ---------------------------------------------------------------------------------------
// optimize

constexpr const char* kOptimizeUsage =
    "usage: graphslam optimize [IN.g2o|IN.npz] [-o OUT.g2o] [-i N] [--algorithm "
    "auto|gn|lm|dogleg]\n"
    "                          [--solver NAME[:ORDERING]] [--init auto|global|none] [--plugin "
    "LIB]...\n"
    "                          [--stats FILE.csv] [--plot FILE.png] [--quiet] [--threads N]\n"
    "                          [--marginals FILE [--marginals-tag TAG]]\n"
    "                          [--robust-kernel NAME[:WIDTH] [--robust-edges "
    "all|loop-closures|TAG]]\n"
    "                          [--reject-outliers [--outliers FILE]] [--drop-unobservable]\n"
    "                          [--objective g2o|chordal] [--information "
    "refuse|nearest-pd|isotropic]\n"
    "                          [--submaps K] [--certify]\n"
    "Optimises a graph and prints one line per iteration and a summary; with ground truth\n"
    "(.npz homework files) also the position errors before and after.\n"
    "Without IN, optimises the built-in default graph (a simulated Manhattan world).\n"
    "Vertices that no line defines (edges-only files) are created from the edges and placed\n"
    "by the global initialisation. Before iterating, every vertex must be determined by its\n"
    "edges: those that are not (no edges, a landmark seen by one range or along one line of\n"
    "bearings) are named and the graph refused (exit 2), or removed with --drop-unobservable.\n"
    "--marginals writes the marginal covariance of every non-fixed vertex at the optimum, one\n"
    "line per vertex: its id, then the upper triangle of its covariance row by row (x y theta:\n"
    "c_xx c_xy c_xt c_yy c_yt c_tt), in the vertex's update coordinates. A vertex fixed only to\n"
    "remove the gauge freedom gets zeros; the others are relative to it.\n"
    "--submaps K splits the graph into K submaps joined by separator vertices: each step is\n"
    "the direct path's (Gauss-Newton, damped when it fails), solved by eliminating every\n"
    "submap's interior onto the separator (--threads submaps at once) and solving the\n"
    "separator system (--solver: cholmod by default; pcg, conjugate gradients in place, holds\n"
    "no factor or copy of it); memory holds the submaps being eliminated and the separator\n"
    "system.\n"
    "A graph without a small separator for K submaps is refused (docs/SUBMAPS.md).";

/// A --stats line: the optimizer's figures, then the step strategy's (IterationStats).
std::string csvLine(const IterationStats& s) {
  std::ostringstream o;
  o.precision(17);
  o << s.iteration << ',' << s.chi2 << ',' << s.step_norm << ',' << s.factorizations << ','
    << s.trials << ',' << (s.accepted ? 1 : 0) << ',' << s.time.linearize << ',' << s.time.build
    << ',' << s.time.factorize << ',' << s.time.solve << ',' << s.elapsed << ',' << s.strategy.step
    << ',' << s.strategy.valuesText();
  return o.str();
}

/// Marginal covariances of the non-fixed vertices (of `tag`, when given) to `path`.
int writeMarginals(Graph& graph, const Registries& reg, const std::string& path,
                   const std::string& tag, const std::string& shown) {
  const TypeRegistry& types = reg.types;
  std::vector<VertexId> ids;
  for (const auto& [id, v] : graph.vertices()) {
    const std::string* t = types.tagOf(*v);
    if (!v->fixed() && (tag.empty() || (t && *t == tag))) ids.push_back(id);
  }
  MarginalCovariance::Options options;
  options.solvers = &reg.solvers;
  MarginalCovariance marginals(options);
  const MarginalSummary summary = marginals.compute(graph, ids);
  std::cout << summary.report() << "\n";
  if (!summary.ok()) {
    std::cerr << "marginal covariances failed: " << summary.message << "\nnot writing " << shown
              << "\n";
    return summary.status == MarginalStatus::kUnconstrained ? kExitBadInput : kExitFailed;
  }
  support::writeFileAtomically(path, [&](std::ostream& out) {
    out << "# graphslam marginal covariances: vertex id, then the upper triangle of its "
           "covariance row by row\n";
    std::string line;
    for (VertexId id : ids) {
      const Eigen::MatrixXd& c = marginals.block(id);
      line = std::to_string(id);
      for (int r = 0; r < c.rows(); ++r) {
        for (int k = r; k < c.cols(); ++k) line += ' ' + support::formatDouble(c(r, k));
      }
      out << line << '\n';
    }
  });
  std::cout << "wrote " << shown << " (" << ids.size() << " vertices)\n";
  return kExitOk;
}

/// Ends the process with `code` once a command's output is written, leaving its graph and
/// factorisation to the system: freeing a million-pose graph object by object takes about
/// 0.5 s, its linear system and factor come on top. (std::exit flushes the streams and runs
/// no destructor of a local.)
[[noreturn]] void exitWithoutFreeing(int code) {
  std::cout.flush();
  std::exit(code);
}

/// The options of graphslam optimize.
struct OptimizeOptions {
  std::string input, output, algorithm, solver, stats_file, plot, npz_model, information;
  std::string objective = "g2o";
  int iterations = 100;
  int submaps = 0;
  std::vector<std::string> plugins;
  std::string damping, first_step, init, marginals_file, marginals_tag, view_page, view_covariance;
  bool quiet = false;
  bool drop_unobservable = false;
  bool certify = false;
  Optimizer::Options options;
  RobustOptions robust;
  OutlierCliOptions outliers;
};

void declareOptimizeOptions(po::options_description& desc, OptimizeOptions& o) {
  Optimizer::Options& options = o.options;
  desc.add_options()("help,h", "show this help")("input", po::value(&o.input),
                                                 "input .g2o file or CMU 16-833 homework .npz")(
      "output,o", po::value(&o.output), "write the optimised graph here (atomically)")(
      "iterations,i", po::value(&o.iterations)->default_value(100), "maximum iterations")(
      "algorithm", po::value(&o.algorithm)->default_value("auto"),
      "auto (Gauss-Newton, LM damping when a step fails), gn (Gauss-Newton), lm "
      "(Levenberg-Marquardt) or dogleg (Powell's dogleg in a trust region)")(
      "solver", po::value(&o.solver)->default_value("auto"),
      "linear solver (see graphslam list-solvers)")(
      "plugin", po::value(&o.plugins)->composing(),
      "load types/solvers from this shared library (repeatable)")(
      "stats", po::value(&o.stats_file), "write per-iteration statistics as CSV")(
      "init", po::value(&o.init)->default_value("auto"),
      "initial guess: none (the file's estimates), global (orientations, then positions, "
      "by linear least squares: chordal relaxation for SE(2) and SE(3) pose graphs) or auto "
      "(none for .npz files, which carry the homework's initial guess; global otherwise)")(
      "npz-model", po::value(&o.npz_model)->default_value("auto"),
      "observations of a .npz file: auto (decided from the file), linear or bearing-range")(
      "objective", po::value(&o.objective)->default_value("g2o"),
      "g2o (chi2 of the edges' own errors) or chordal (SE-Sync's problem for pose graphs: "
      "EDGE_SE2 and EDGE_SE3:QUAT as chordal rotation and translation terms with SE-Sync's "
      "isotropic weights; the summary's chi2 is then SE-Sync's f)")(
      "information", po::value(&o.information)->default_value("refuse"),
      "information matrices that are not positive definite: refuse (an error listing "
      "them), nearest-pd (eigenvalues raised to 1e-6 of the largest) or isotropic (one "
      "weight per translation and rotation block, as SE-Sync derives them)")(
      "plot", po::value(&o.plot),
      "draw the initial and final positions (and the ground truth) into this PNG")(
      "quiet,q", "print only the summary")(
      "threads", po::value(&options.threads)->default_value(options.threads),
      "threads reading a .g2o file and evaluating errors and Jacobians (the result is the "
      "same for every count)")("step-tolerance",
                               doubleValue(&options.step_tolerance, options.step_tolerance),
                               "converged when the Euclidean norm of the update is below this")(
      "function-tolerance", doubleValue(&options.function_tolerance, options.function_tolerance),
      "converged when chi2 falls by less than this fraction (0: off)")(
      "lambda-init", doubleValue(&options.initial_lambda_factor, options.initial_lambda_factor),
      "LM initial damping factor")(
      "lambda-decrease", doubleValue(&options.min_lambda_decrease, options.min_lambda_decrease),
      "LM: largest shrink of lambda after a good step (factor)")(
      "first-step", po::value(&o.first_step)->default_value("dogleg"),
      "default algorithm, when the first Gauss-Newton step raises chi2: dogleg (a dogleg "
      "step in a trust region shrunk until the model agrees, same factorisation) or gn "
      "(keep the Gauss-Newton step)")(
      "damping", po::value(&o.damping)->default_value("identity"),
      "LM damping: identity (lambda I) or diagonal (lambda diag(H))")(
      "marginals", po::value(&o.marginals_file),
      "write marginal covariances (upper triangle per vertex) here, atomically")(
      "marginals-tag", po::value(&o.marginals_tag),
      "only vertices of this .g2o tag (e.g. VERTEX_XY for the landmarks)")(
      "submaps", po::value(&o.submaps)->default_value(0),
      "optimise by K submaps (Schur complement onto their separator, exact steps; 0: the "
      "direct path)")(
      "drop-unobservable",
      "remove the vertices the edges do not determine (no edges, a landmark seen by one "
      "range or by parallel bearings) and their edges before optimising; without it such a "
      "graph is refused (exit 2)")(
      "certify",
      "first certify the global optimum of SE-Sync's objective (graphslam certify: pose "
      "graphs only; isotropic weights from the edges' information), then refine the chosen "
      "--objective from the certified poses; the report names the objective certified");
  declareRobustOptions(desc, o.robust);
  declareOutlierOptions(desc, o.outliers);
  declareViewOptions(desc, o.view_page, o.view_covariance);
}

/// Parses and checks the options and fills the optimizer's; false after --help.
bool parseOptimizeOptions(const std::vector<std::string>& args, OptimizeOptions& o) {
  po::options_description desc("options");
  declareOptimizeOptions(desc, o);
  po::positional_options_description pos;
  pos.add("input", 1);
  const auto vm = parse(args, desc, &pos);
  if (vm.count("help")) {
    printHelp(kOptimizeUsage, desc);
    return false;
  }
  Optimizer::Options& options = o.options;
  if (o.iterations < 1) throw UsageError("--iterations must be at least 1");
  if (o.submaps < 0) throw UsageError("--submaps must be at least 1 (0: the direct path)");
  if (o.submaps > 0 && o.algorithm != "auto") {
    throw UsageError(
        "--submaps takes its own steps (Gauss-Newton, damped when one fails): --algorithm "
        "does not apply");
  }
  if (o.submaps > 0 && o.solver.find(':') != std::string::npos) {
    throw UsageError(
        "--submaps: --solver names the separator system's solver, which takes "
        "the system in its own order: no :ORDERING");
  }
  if (options.threads < 1 || options.threads > 256) {
    throw UsageError("--threads must be between 1 and 256");
  }
  // Written so that NaN fails too.
  if (!(options.initial_lambda_factor > 0 && std::isfinite(options.initial_lambda_factor))) {
    throw UsageError("--lambda-init must be a positive finite number");
  }
  if (!(options.min_lambda_decrease > 0 && options.min_lambda_decrease <= 1)) {
    throw UsageError("--lambda-decrease must be in (0, 1]");
  }
  if (!(options.function_tolerance >= 0 && std::isfinite(options.function_tolerance))) {
    throw UsageError("--function-tolerance must be a finite number >= 0");
  }
  if (!(options.step_tolerance >= 0 && std::isfinite(options.step_tolerance))) {
    throw UsageError("--step-tolerance must be a finite number >= 0");
  }
  options.damping = parseChoice<Optimizer::Options::Damping>(
      "damping", o.damping,
      {{"identity", Optimizer::Options::Damping::kIdentity},
       {"diagonal", Optimizer::Options::Damping::kDiagonal}});
  options.first_step_dogleg =
      parseChoice<bool>("first-step", o.first_step, {{"dogleg", true}, {"gn", false}});
  options.algorithm = parseAlgorithm(o.algorithm);
  checkObjective(o.objective);
  options.max_iterations = o.iterations;
  options.linear_solver = o.solver;
  o.quiet = vm.count("quiet") != 0;
  o.drop_unobservable = vm.count("drop-unobservable") != 0;
  o.certify = vm.count("certify") != 0;
  checkOutlierOptions(vm, o.outliers);
  if (!o.view_covariance.empty() && o.view_page.empty()) {
    throw UsageError("--view-covariance needs --view PAGE.html");
  }
  if (o.certify && o.outliers.reject) {
    throw UsageError(
        "--certify and --reject-outliers do not go together (the certificate is "
        "of every edge's terms)");
  }
  return true;
}

/// Checks --solver and --marginals-tag against the registries.
void checkRegistered(const OptimizeOptions& o, const Registries& reg) {
  checkSolverSpec(o.solver, reg.solvers);
  if (!o.marginals_tag.empty()) {
    const auto* entry = reg.types.find(o.marginals_tag);
    if (o.marginals_file.empty()) throw UsageError("--marginals-tag needs --marginals FILE");
    if (!entry || entry->kind != TypeRegistry::Kind::kVertex) {
      throw UsageError("--marginals-tag: '" + o.marginals_tag +
                       "' is not a vertex tag (graphslam list-types shows them)");
    }
  }
}

/// The input file, or the built-in default graph without one.
LoadedInput loadOptimizeInput(const OptimizeOptions& o, const Registries& reg) {
  InputOptions input_options;
  input_options.npz_model = o.npz_model;
  input_options.threads = o.options.threads;
  input_options.information = parseInformationRepair(o.information);
  checkInitChoice(o.init);
  LoadedInput in;
  if (o.input.empty()) {
    simulation::ManhattanOptions sim;
    std::cout
        << "no input given: optimising the built-in default graph (simulated Manhattan world, "
        << sim.num_poses << " poses, seed " << sim.seed << ")\n";
    auto simulated = simulation::simulateManhattan(sim);
    in.graph = std::move(simulated.graph);
  } else {
    in = loadInput(o.input, reg, input_options);
    std::cout << o.input << ": " << in.description << "\n";
    for (const auto& note : in.notes) std::cout << "  " << note << "\n";
  }
  std::cout << "graph: " << in.graph.numVertices() << " vertices, " << in.graph.numEdges()
            << " edges\n";
  return in;
}

/// Optimises `graph`, printing a line per iteration (unless quiet) and the summary, and
/// collecting the lines of --stats in `csv`.
Summary runOptimizer(Graph& graph, const SolverRegistry& solvers, OptimizeOptions& o,
                     std::vector<std::string>& csv, ViewRecorder& recorder) {
  const bool quiet = o.quiet;
  o.options.callback = [&csv, quiet](const IterationStats& s) {
    if (!quiet) {
      const std::string note = !s.accepted               ? "  (rejected)"
                               : s.strategy.note.empty() ? std::string()
                                                         : "  (" + s.strategy.note + ")";
      std::printf("iter %3d  chi2 %.10g  lambda %.3e  step %.3e  time %.4f s%s\n", s.iteration,
                  s.chi2, s.strategy.value("lambda"), s.step_norm, s.time.total(), note.c_str());
      std::fflush(stdout);
    }
    csv.push_back(csvLine(s));
  };
  recorder.record(o.options, graph);
  support::setLogLevel(support::LogLevel::kInfo);
  support::setLogSink([](support::LogLevel level, const std::string& msg) {
    std::fprintf(level >= support::LogLevel::kWarning ? stderr : stdout, "%s: %s\n",
                 toString(level), msg.c_str());
  });
  Optimizer optimizer(graph, solvers, o.options);
  const Summary summary = optimizer.optimize();
  std::cout << summary.report() << "\n";
  return summary;
}

void writeStats(const std::string& path, const std::vector<std::string>& csv) {
  support::writeFileAtomically(path, [&](std::ostream& out) {
    out << "iteration,chi2,step_norm,factorizations,trials,accepted,time_linearize,time_build,"
           "time_factorize,time_solve,elapsed,step,strategy\n";
    for (const auto& line : csv) out << line << "\n";
  });
}

void plotOptimized(const OptimizeOptions& o, const std::string& png, const Summary& summary,
                   const Graph& graph, const std::map<VertexId, Eigen::Vector2d>& initial_positions,
                   const io::PointGroundTruth& truth) {
  std::ostringstream title;
  title << (o.input.empty() ? std::string("built-in default graph")
                            : std::filesystem::path(o.input).filename().string())
        << ": chi2 " << summary.initial_chi2 << " -> " << summary.final_chi2 << " ("
        << toString(summary.algorithm) << ", " << summary.iterations << " iterations)";
  plotPoints(png, title.str(), graph, initial_positions, truth, o.plot);
}

/// Writes every requested output to its staged file, then puts them in place together;
/// returns the exit code (on a failure nothing is put in place).
int writeOptimizeOutputs(OutputSet& outputs, const OptimizeOptions& o, Graph& graph,
                         const Registries& reg, const LoadedInput& in, const Summary& summary,
                         const std::vector<std::string>& csv, const outliers::GncResult& gnc,
                         const std::map<VertexId, Eigen::Vector2d>& initial_positions,
                         ViewRecorder& recorder, const std::vector<VertexId>& view_ids) {
  return outputs.writeAll([&] {
    if (!o.marginals_file.empty()) {  // first: it is the output that may fail on its own
      const int rc = writeMarginals(graph, reg, outputs.staged(o.marginals_file), o.marginals_tag,
                                    o.marginals_file);
      if (rc != kExitOk) {
        outputs.abort();
        std::cerr << "no output written\n";
        return rc;
      }
    }
    if (!o.stats_file.empty()) writeStats(outputs.staged(o.stats_file), csv);
    if (!o.outliers.outliers_file.empty()) {
      writeOutliersFile(outputs.staged(o.outliers.outliers_file), gnc, in.edge_lines,
                        o.outliers.outliers_file);
    }
    if (!o.output.empty()) {
      io::saveG2o(outputs.staged(o.output), graph, reg.types);
      std::cout << "wrote " << o.output << "\n";
    }
    if (!o.plot.empty()) {
      plotOptimized(o, outputs.staged(o.plot), summary, graph, initial_positions, in.ground_truth);
    }
    if (recorder.on()) {
      recorder.write(outputs.staged(o.view_page), graph, reg, in, optimizerSummaryLines(summary),
                     &gnc, view_ids);
      std::cout << "wrote " << o.view_page << "\n";
    }
    outputs.commit();
    return kExitOk;
  });
}

int cmdOptimize(const std::vector<std::string>& args) {
  OptimizeOptions o;
  if (!parseOptimizeOptions(args, o)) return kExitOk;
  Registries reg;
  loadRegistries(reg, o.plugins);
  checkRegistered(o, reg);
  checkRobustOptions(o.robust, reg);
  // Every output is checked before the work starts and written all or nothing.
  OutputSet outputs(
      {o.output, o.stats_file, o.plot, o.marginals_file, o.outliers.outliers_file, o.view_page},
      {o.input});
  ViewRecorder recorder(o.view_page);
  if (!o.plot.empty() && findPlotPython().empty()) {
    throw UsageError(
        "--plot needs Python 3 with matplotlib, and none was found (tried "
        "$GRAPHSLAM_PYTHON, /usr/bin/python3, python3)");
  }
  LoadedInput in = loadOptimizeInput(o, reg);
  Graph& graph = in.graph;
  const std::vector<VertexId> view_ids = o.view_covariance.empty()
                                             ? std::vector<VertexId>{}
                                             : parseIdList(o.view_covariance, "view-covariance");
  checkVertexIds(graph, view_ids, "view-covariance");
  if (!checkFiniteTerms(in, o.output)) {
    outputs.abort();
    exitWithoutFreeing(kExitFailed);
  }
  if (o.outliers.reject) {
    initializeFromKnownInliers(in, graph, o.init, reg.solvers, o.outliers);
  } else {
    applyInitialGuess(in, graph, o.init, reg.solvers);
  }
  // Before iterating: every vertex must be determined by its edges (or be dropped).
  if (!checkBeforeSolving(in, reg.types, o.drop_unobservable, o.options.threads, o.quiet)) {
    outputs.abort();
    exitWithoutFreeing(kExitBadInput);
  }
  outliers::GncResult gnc;
  if (o.outliers.reject) recorder.captureEdgeTags(graph, reg.types);
  if (o.outliers.reject &&
      !rejectOutliersForOptimize(graph, reg.solvers, o.options, o.outliers, o.quiet, gnc)) {
    outputs.abort();
    exitWithoutFreeing(kExitFailed);
  }
  if (o.certify) (void)certifyBeforeOptimize(graph, reg.types, o.input);
  applyRobustOptions(o.robust, graph, reg);
  // Kept for the plot only (a map entry per vertex: 80 MB on a million poses).
  const auto initial_positions = o.plot.empty() ? decltype(positions(graph)){} : positions(graph);
  const auto initial_errors = eval::positionErrors(graph, in.ground_truth);

  const auto objective = applyObjective(o.objective, graph);
  std::vector<std::string> csv;
  recorder.captureInitial(graph, "start (--init " + o.init + ")");
  const Summary summary =
      o.submaps > 0 ? runSubmapSolver(graph, reg.solvers, o.submaps, o.options, o.quiet, csv)
                    : runOptimizer(graph, reg.solvers, o, csv, recorder);
  finishObjective(objective.get(), graph);
  if (!in.ground_truth.empty()) {
    const auto final_errors = eval::positionErrors(graph, in.ground_truth);
    std::printf("position error vs ground truth (m), initial -> final:\n");
    printErrors("poses", initial_errors.poses, final_errors.poses);
    printErrors("landmarks", initial_errors.landmarks, final_errors.landmarks);
  }
  if (!summary.succeeded() && summary.status != TerminationStatus::kNoProgress) {
    std::cerr << "optimisation failed: " << toString(summary.status) << ": " << summary.message
              << "\n";
    const auto& edges = summary.failed_vertex_edges;
    const std::string lines = edgeLines(edges, in.edge_lines, graph.numEdges());
    if (summary.failed_vertex >= 0 && !lines.empty()) {
      std::cerr << "vertex " << summary.failed_vertex << ": "
                << (edges.size() == 1 ? "its edge is on " : "its edges are on ") << lines << " of "
                << o.input << "\n";
    }
    std::cerr << failedEdgeNote(summary.failed_edge, in.edge_lines, graph.numEdges(), o.input);
    if (!o.output.empty()) std::cerr << "not writing " << o.output << "\n";
    outputs.abort();
    exitWithoutFreeing(kExitFailed);
  }
  if (!checkUndampedAtResult(in, summary, reg.solvers)) {
    outputs.abort();
    exitWithoutFreeing(kExitFailed);
  }
  exitWithoutFreeing(writeOptimizeOutputs(outputs, o, graph, reg, in, summary, csv, gnc,
                                          initial_positions, recorder, view_ids));
}

}  // namespace

// The tool's commands, run by the graphslam launcher (main.cpp) once it has checked the
// command's name: loaded only when a command runs.
extern "C" __attribute__((visibility("default"))) int graphslam_tool_run(int argc, char** argv) {
#ifdef __GLIBC__
  // Large arrays (the factor, H, the graph's edge lists) come from mmap and go back to the
  // system when freed. glibc's default raises the mmap threshold to 32 MB after the first
  // such free, after which freed arrays below that stay in the heap: on a 1M-pose graph the
  // initial guess's freed systems then add about 110 MB to the optimizer's peak.
  mallopt(M_MMAP_THRESHOLD, 4 << 20);
  mallopt(M_TRIM_THRESHOLD, 4 << 20);
#endif
  configureProcess();
  const std::string command = argv[1];
  const std::vector<std::string> args(argv + 2, argv + argc);
  try {
    if (command == "optimize") return cmdOptimize(args);
    if (command == "list-types") return cmdListTypes(args);
    if (command == "list-solvers") return cmdListSolvers(args);
    if (command == "list-kernels") return cmdListKernels(args);
    if (command == "simulate") return cmdSimulate(args);
    if (command == "eval") return cmdEval(args);
    if (command == "deadreckon") return cmdDeadreckon(args);
    if (command == "convert") return cmdConvert(args);
    if (command == "info") return cmdInfo(args);
    if (command == "drivebot") return cmdDrivebot(args);
    if (command == "solvers") return cmdSolvers(args);
    if (command == "add-outliers") return cmdAddOutliers(args);
    if (command == "incremental") return cmdIncremental(args);
    if (command == "view") return cmdView(args);
    if (command == "calibrate") return cmdCalibrate(args);
    if (command == "certify") return cmdCertify(args);
    std::cerr << "graphslam: unknown command '" << printable(command) << "'\n\n" << kMainUsage;
    return kExitBadInput;
  } catch (const po::error& e) {
    std::cerr << "graphslam " << command << ": " << printable(e.what()) << " (see graphslam "
              << command << " --help)\n";
    return kExitBadInput;
  } catch (const UsageError& e) {
    std::cerr << "graphslam " << command << ": " << printable(e.what()) << " (see graphslam "
              << command << " --help)\n";
    return kExitBadInput;
  } catch (const Error& e) {
    std::cerr << "graphslam " << command << ": " << printable(e.what()) << "\n";
    return kExitBadInput;
  } catch (const std::bad_alloc&) {
    exitOutOfMemory(command);
  } catch (const std::exception& e) {
    std::cerr << "graphslam " << command << ": internal error: " << printable(e.what()) << "\n";
    return kExitFailed;
  }
}
