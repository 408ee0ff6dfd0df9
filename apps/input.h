// SPDX-License-Identifier: MIT
// The tool's input loader: every subcommand that reads a graph goes through loadInput(), so
// each reads the same formats (the io module's format registry: .g2o, TORO, iSAM, the CMU
// homework's .npz, the relative-pose matrix), from a path, "-" (standard input), a pipe or
// a FIFO, read once.
//
//   Registries reg;  loadRegistries(reg, plugins);
//   LoadedInput in = loadInput(path, reg);       // throws InputError on bad input
//   Graph& g = in.graph;                          // ready to optimise
//   if (!in.ground_truth.empty()) ...             // true positions (.npz only)
#pragma once

#include <map>
#include <string>
#include <vector>

#include "cli_common.h"
#include "graphslam/core/graph.h"
#include "graphslam/core/linear_solver.h"
#include "graphslam/diagnostics/information.h"
#include "graphslam/io/graph_file.h"

namespace graphslam::apps {

struct InputOptions {
  /// Observation model of a .npz homework file: auto (decided from the file), linear or
  /// bearing-range.
  std::string npz_model = "auto";
  /// Threads parsing a .g2o file (io::LoadOptions::threads).
  int threads = 1;
  /// Information matrices that are not positive definite: refused or repaired
  /// (io::LoadOptions::information).
  InformationRepair information = InformationRepair::kRefuse;
  /// Vertices that no line defines are created from the edges (io::LoadOptions::
  /// create_missing_vertices): the tool reads edges-only files (SE-Sync's, KITTI's).
  bool create_missing_vertices = true;
  /// The input's format: auto (the registry's detection) or a graph format's name.
  std::string format = "auto";
  /// Format-specific choices (io::ReadContext::choices), e.g. the matrix's "loop-closure".
  std::map<std::string, std::string> choices;
};

/// Checks a --from value: auto or a readable graph format of the registry; throws
/// UsageError listing them otherwise.
void checkGraphFormat(const std::string& format, const Registries& reg);

/// Parses refuse|nearest-pd|isotropic (--information); throws UsageError otherwise.
[[nodiscard]] InformationRepair parseInformationRepair(const std::string& text);

/// A graph read from a file, with what came with it.
using LoadedInput = io::GraphFile;

/// Loads `path` as described above. Throws graphslam::InputError whose message holds
/// every diagnostic (`FILE:LINE: ...` for .g2o, `FILE: array 'NAME': ...` for .npz).
[[nodiscard]] LoadedInput loadInput(const std::string& path, const Registries& reg,
                                    const InputOptions& options = {});

/// For a graph with vertices created from edges, which have no estimates of their own: the
/// global initialisation (SE(2) poses and landmarks), saying so; nothing otherwise.
void initializeCreatedVertices(const LoadedInput& in, Graph& graph, const SolverRegistry& solvers);

/// Checks an --init value (auto|global|none); throws UsageError otherwise.
void checkInitChoice(const std::string& init);

/// The tool's initial guess, as `optimize` makes it: `init` is auto (global for .g2o
/// inputs, the file's own estimates for inputs that keep theirs), global (init::
/// initializeGraph, solved with the "auto" solver) or none. Prints one line on what was done.
void applyInitialGuess(const LoadedInput& in, Graph& graph, std::string init,
                       const SolverRegistry& solvers);

}  // namespace graphslam::apps
