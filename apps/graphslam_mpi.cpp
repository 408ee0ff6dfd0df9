// SPDX-License-Identifier: MIT
// graphslam-mpi: the submap solver across MPI ranks (docs/SUBMAPS.md), launched by mpirun:
//   mpirun -np 3 graphslam-mpi IN.g2o --submaps 6 [-o OUT.g2o] [-i N] [--threads N]
//                              [--solver cholmod|pcg|NAME]
// Every rank reads IN and computes the same initial guess and partition; rank 0 prints the
// progress (with the bytes the ranks exchanged) and writes OUT.
#include <boost/program_options.hpp>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>

#include "graphslam/init/initial_guess.h"
#include "graphslam/io/g2o.h"
#include "graphslam/solvers/process.h"
#include "graphslam/solvers/register.h"
#include "graphslam/submap/mpi_solver.h"
#include "graphslam/support/error.h"
#include "graphslam/types_slam2d/register.h"
#include "graphslam/types_slam3d/register.h"

namespace po = boost::program_options;
using namespace graphslam;

namespace {

constexpr const char* kUsage =
    "usage: mpirun -np RANKS graphslam-mpi IN.g2o --submaps K [-o OUT.g2o] [-i N] [--threads N]\n"
    "                                      [--init global|none] [--solver NAME] [--quiet]\n"
    "Optimises a 2D or 3D graph by K submaps spread over the MPI ranks (rank r holds submaps\n"
    "r, r + RANKS, ...): each rank eliminates its submaps' interiors and sends rank 0 their\n"
    "separator blocks; rank 0 solves the separator system (--solver: cholmod by default; pcg,\n"
    "conjugate gradients in place) and broadcasts the step. The result\n"
    "is that of graphslam optimize --submaps K. Exit 0 on success, 1 when the optimisation\n"
    "fails, 2 for bad arguments or input. A rank that dies makes mpirun stop every rank.";

struct Arguments {
  std::string input, output, init = "global", solver = "cholmod";
  int submaps = 0, iterations = 100, threads = 1;
  bool quiet = false;
};

/// Parses the arguments; returns the exit code to stop with, or -1 to go on.
int parseArguments(int argc, char** argv, Arguments& a, bool root) {
  po::options_description desc("options");
  desc.add_options()("help,h", "show this help")("input", po::value(&a.input), "input .g2o file")(
      "output,o", po::value(&a.output), "write the optimised graph here (rank 0, atomically)")(
      "submaps", po::value(&a.submaps), "number of submaps (at least the number of ranks)")(
      "iterations,i", po::value(&a.iterations)->default_value(100), "maximum iterations")(
      "threads", po::value(&a.threads)->default_value(1), "threads per rank")(
      "init", po::value(&a.init)->default_value("global"), "initial guess: global or none")(
      "solver", po::value(&a.solver)->default_value("cholmod"),
      "the separator system's solver on rank 0: pcg (conjugate gradients in place, no factor) "
      "or a sparse Cholesky of `graphslam list-solvers` (cholmod)")("quiet,q",
                                                                    "print only the summary");
  po::positional_options_description pos;
  pos.add("input", 1);
  po::variables_map vm;
  po::store(po::command_line_parser(argc, argv).options(desc).positional(pos).run(), vm);
  po::notify(vm);
  if (vm.count("help")) {
    if (root) std::cout << kUsage << "\n\n" << desc;
    return 0;
  }
  a.quiet = vm.count("quiet") != 0;
  std::string problem;
  if (a.input.empty()) problem = "no input file";
  if (a.submaps < 1) problem = "--submaps K (at least 1) is required";
  if (a.iterations < 1) problem = "--iterations must be at least 1";
  if (a.threads < 1 || a.threads > 256) problem = "--threads must be between 1 and 256";
  if (a.init != "global" && a.init != "none") problem = "--init must be global or none";
  if (problem.empty()) return -1;
  if (root) std::cerr << "graphslam-mpi: " << problem << " (see graphslam-mpi --help)\n";
  return 2;
}

int run(const Arguments& a, const submap::MpiSession& mpi) {
  const bool root = mpi.rank() == 0;
  TypeRegistry types;
  types_slam2d::registerTypes(types);
  types_slam3d::registerTypes(types);
  // CHOLMOD's calls run their OpenMP loops serially (it asks for 4 threads whatever the
  // cores), and BLAS runs on one thread per call unless OPENBLAS_NUM_THREADS says otherwise:
  // ranks and --threads are how this program uses the cores.
  solvers::serializeCholmodOpenMp();
  if (std::getenv("OPENBLAS_NUM_THREADS") == nullptr) (void)solvers::setBlasThreads(1);
  solvers::retainFreedMemory();  // every submap's factor is made and freed once or twice a step
  SolverRegistry solvers;
  solvers::registerSolvers(solvers);
  if (a.solver != "pcg" &&
      (a.solver.find(':') != std::string::npos || !solvers.contains(a.solver))) {
    if (root) {  // before reading the file: every rank stops alike
      std::cerr << "graphslam-mpi: --solver " << a.solver
                << ": not a separator solver (pcg, or a solver of graphslam list-solvers, "
                   "without :ORDERING)\n";
    }
    return 2;
  }
  io::LoadResult loaded = io::loadG2o(a.input, types);
  if (!loaded.ok()) {  // every rank reads the same file and stops alike
    if (root) std::cerr << "graphslam-mpi: " << loaded.diagnostics.front().str() << "\n";
    return 2;
  }
  Graph& graph = loaded.graph;
  if (a.init == "global") (void)init::initializeGraph(graph, solvers);
  submap::Options options;
  options.partition.num_submaps = a.submaps;
  options.max_iterations = a.iterations;
  options.threads = a.threads;
  if (a.solver == "pcg") {
    options.separator_method = submap::Options::SeparatorMethod::conjugate_gradients;
  } else {
    options.separator_solver = a.solver;
  }
  options.solvers = solvers.contains(options.separator_solver) ? &solvers : nullptr;
  if (root) {
    std::printf("%s: %zu vertices, %zu edges; %d ranks, %d submaps\n", a.input.c_str(),
                graph.numVertices(), graph.numEdges(), mpi.size(), a.submaps);
    if (!a.quiet) {
      options.callback = [](const submap::IterationStats& s) {
        std::printf(
            "iter %3d  chi2 %.10g  gradient %.3e  step %.3e  separator %zu vertices%s  "
            "communicated %.3f MB  time %.4f s%s\n",
            s.iteration, s.chi2, s.gradient_norm, s.step_norm, s.separator_vertices,
            s.separator_iterations > 0
                ? (" (" + std::to_string(s.separator_iterations) + " CG iterations)").c_str()
                : "",
            static_cast<double>(s.bytes_communicated) / 1e6, s.time,
            s.accepted ? "" : "  (rejected)");
        std::fflush(stdout);
      };
    }
  }
  const submap::Summary summary = submap::MpiSubmapSolver(graph, options).optimize();
  if (!root) return summary.succeeded() ? 0 : 1;
  std::cout << summary.report() << "\n";
  if (!summary.succeeded()) {
    std::cerr << "optimisation failed: " << toString(summary.status) << ": " << summary.message
              << "\n";
    if (!a.output.empty()) std::cerr << "not writing " << a.output << "\n";
    return 1;
  }
  if (!a.output.empty()) {
    io::saveG2o(a.output, graph, types);
    std::cout << "wrote " << a.output << "\n";
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  submap::MpiSession mpi(argc, argv);
  const bool root = mpi.rank() == 0;
  try {
    Arguments a;
    const int rc = parseArguments(argc, argv, a, root);
    if (rc >= 0) return rc;
    return run(a, mpi);
  } catch (const po::error& e) {
    if (root) std::cerr << "graphslam-mpi: " << e.what() << " (see graphslam-mpi --help)\n";
    return 2;
  } catch (const Error& e) {  // the same on every rank: the input and partition are shared
    if (root) std::cerr << "graphslam-mpi: " << e.what() << "\n";
    return 2;
  }
}
