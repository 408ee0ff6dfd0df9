// SPDX-License-Identifier: MIT
// Shared by the dataset benchmark programs (bench/factor_limit.cpp, bench/ceres_compare.cpp):
// load a .g2o file as `graphslam optimize` does by default (strict loading, global
// initialisation), time things, keep and restore estimates, parse simple arguments.
#pragma once

#include <dlfcn.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "graphslam/core/graph.h"
#include "graphslam/core/linear_solver.h"
#include "graphslam/core/type_registry.h"
#include "graphslam/init/chordal_se3.h"
#include "graphslam/init/global_se2.h"
#include "graphslam/io/g2o.h"
#include "graphslam/solvers/options.h"
#include "graphslam/solvers/process.h"
#include "graphslam/solvers/register.h"
#include "graphslam/support/large_array.h"
#include "graphslam/support/logging.h"
#include "graphslam/types_slam2d/register.h"
#include "graphslam/types_slam3d/register.h"

namespace graphslam::bench {

/// Exit code ctest treats as "skipped" (SKIP_RETURN_CODE): the dataset is absent.
constexpr int kExitSkipped = 77;
constexpr int kExitBadInput = 2;

using Clock = std::chrono::steady_clock;

[[nodiscard]] inline double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

[[nodiscard]] inline double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

/// Makes every OpenMP parallel region of this process serial (max-active-levels 0), for
/// graphslam's and Ceres' CHOLMOD alike: Debian's CHOLMOD asks for 4 OpenMP threads in
/// each supernode's scatter loop whatever OMP_NUM_THREADS says, which on 2 cores made its
/// factorisation 2-3x slower (its BLAS keeps OPENBLAS_NUM_THREADS threads). Returns what
/// it did, for the output ("serial", or "none" without an OpenMP runtime in the process).
inline const char* serialiseOpenMp() {
  auto* set = reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "omp_set_max_active_levels"));
  if (!set) return "none";
  set(0);
  return "serial";
}

/// Thrown for bad input (message printed, exit code 2).
struct BadInput : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The types of types_slam2d and types_slam3d and every solver of this build, the solvers sharing
/// one cache of block orderings as the tool's do.
struct Registries {
  TypeRegistry types;
  SolverRegistry solvers;
  Registries() {
    types_slam2d::registerTypes(types);
    types_slam3d::registerTypes(types);
    solvers::SolverOptions options;
    options.ordering_cache = std::make_shared<solvers::OrderingCache>();
    solvers::registerSolvers(solvers, options);
  }
};

/// Runs a program's body with library warnings on stderr and maps exceptions to exit codes:
/// BadInput 2, anything else 1.
template <typename Body>
int guardedMain(Body&& body) {
  support::setLogLevel(support::LogLevel::kWarning);
  // The process-wide settings the graphslam tool makes, so that the figures compare
  // (OpenMP: serialiseOpenMp(), for every OpenMP user of the program).
  solvers::installCholmodPrefaultingAllocator();
  support::setLargeArrayRetention(support::LargeArrayRetention{});
  try {
    return body();
  } catch (const BadInput& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}

/// Loads `path` strictly and applies the tool's default initial guess
/// (init::initializeGlobal, init::initializeChordal3d). Throws BadInput on a bad file.
[[nodiscard]] inline io::LoadResult loadInitialised(const std::string& path,
                                                    const TypeRegistry& types) {
  io::LoadResult r = io::loadG2o(path, types);
  if (!r.ok()) {
    std::string msg = path + ": cannot load";
    for (const auto& d : r.diagnostics) msg += "\n" + d.str();
    throw BadInput(msg);
  }
  (void)init::initializeGlobal(r.graph);
  (void)init::initializeChordal3d(r.graph);
  return r;
}

/// The flat estimates of all vertices, in id order (to start several solvers from the
/// same point).
[[nodiscard]] inline std::vector<std::vector<double>> saveEstimates(const Graph& graph) {
  std::vector<std::vector<double>> out;
  out.reserve(graph.numVertices());
  for (const auto& [id, v] : graph.vertices()) {
    out.emplace_back(static_cast<std::size_t>(v->estimateDataDimension()));
    v->getEstimateData(out.back().data());
  }
  return out;
}

inline void restoreEstimates(Graph& graph, const std::vector<std::vector<double>>& saved) {
  std::size_t k = 0;
  for (const auto& [id, v] : graph.vertices()) v->setEstimateData(saved.at(k++).data());
}

/// Minimal argument parsing: FILE plus `--name value` options with defaults.
class Args {
 public:
  Args(int argc, char** argv, const char* usage) : usage_(usage) {
    for (int i = 1; i < argc; ++i) {
      std::string a = argv[i];
      if (a == "-h" || a == "--help") {
        std::printf("%s\n", usage);
        std::exit(0);
      }
      if (a.rfind("--", 0) == 0) {
        if (i + 1 >= argc) fail("option " + a + " needs a value");
        options_.emplace_back(a.substr(2), argv[++i]);
      } else if (file_.empty()) {
        file_ = a;
      } else {
        fail("unexpected argument '" + a + "'");
      }
    }
    if (file_.empty()) fail("no input file given");
  }

  [[nodiscard]] const std::string& file() const { return file_; }

  [[nodiscard]] std::string text(const std::string& name, const std::string& fallback) {
    for (auto& [n, v] : options_) {
      if (n == name) {
        n.clear();  // consumed
        return v;
      }
    }
    return fallback;
  }
  [[nodiscard]] double number(const std::string& name, double fallback) {
    const std::string v = text(name, "");
    if (v.empty()) return fallback;
    char* end = nullptr;
    const double x = std::strtod(v.c_str(), &end);
    if (!end || *end != '\0') fail("--" + name + " expects a number, not '" + v + "'");
    return x;
  }
  [[nodiscard]] int integer(const std::string& name, int fallback, int minimum) {
    const double x = number(name, fallback);
    if (x != static_cast<int>(x) || x < minimum) {
      fail("--" + name + " expects an integer >= " + std::to_string(minimum));
    }
    return static_cast<int>(x);
  }
  /// Fails on options nobody asked for (call after reading all of them).
  void finish() const {
    for (const auto& [n, v] : options_) {
      if (!n.empty()) fail("unknown option --" + n);
    }
  }

  /// Exits with code 77 (skipped) when the file does not exist.
  void skipIfAbsent() const {
    if (!std::filesystem::exists(file_)) {
      std::printf("skipped: %s not found (datasets are looked up through GRAPHSLAM_DATA)\n",
                  file_.c_str());
      std::exit(kExitSkipped);
    }
  }

  /// A bad argument: the message and the usage on stderr, exit kExitBadInput.
  [[noreturn]] void fail(const std::string& msg) const {
    std::fprintf(stderr, "error: %s\n%s\n", msg.c_str(), usage_);
    std::exit(kExitBadInput);
  }

 private:
  const char* usage_;
  std::string file_;
  std::vector<std::pair<std::string, std::string>> options_;
};

}  // namespace graphslam::bench
