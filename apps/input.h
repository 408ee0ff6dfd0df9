// SPDX-License-Identifier: MIT
// The tool's input loader: every subcommand that reads a graph goes through loadInput(), so
// each reads the same formats.
//
//   Registries reg;  loadRegistries(reg, plugins);
//   LoadedInput in = loadInput(path, reg.types);      // throws InputError on bad input
//   Graph& g = in.graph;                               // ready to optimise
//   if (!in.ground_truth.empty()) ...                  // true positions (.npz only)
//
// Formats, by extension (case-insensitive):
//   .npz  a CMU 16-833 HW3 homework archive (types_slam2d/coursework_npz.h): point robot,
//         poses 0..P-1 then landmarks P..P+L-1, the homework's initial guess, ground truth;
//   else  a .g2o file read through the type registry (no ground truth), or a TORO or iSAM
//         file (formats/text_format.h: recognised by its tags), translated to .g2o text
//         and read the same way.
#pragma once

#include <string>
#include <vector>

#include "graphslam/core/graph.h"
#include "graphslam/core/information.h"
#include "graphslam/core/linear_solver.h"
#include "graphslam/core/type_registry.h"
#include "graphslam/formats/text_format.h"
#include "graphslam/homework/coursework_npz.h"
#include "graphslam/homework/point_ground_truth.h"

namespace graphslam::apps {

struct InputOptions {
  /// Observation model of a .npz homework file (kAuto: decided from the file).
  homework::PointObservationModel npz_model = homework::PointObservationModel::kAuto;
  /// Threads parsing a .g2o file (io::LoadOptions::threads).
  int threads = 1;
  /// Information matrices that are not positive definite: refused or repaired
  /// (io::LoadOptions::information).
  InformationRepair information = InformationRepair::kRefuse;
  /// Vertices that no line defines are created from the edges (io::LoadOptions::
  /// create_missing_vertices): the tool reads edges-only files (SE-Sync's, KITTI's).
  bool create_missing_vertices = true;
  /// Text input format: auto (formats::detectFileFormat), g2o, toro or isam.
  std::string text_format = "auto";
};

/// Parses g2o|toro|isam; throws UsageError otherwise.
[[nodiscard]] formats::TextFormat parseTextFormat(const std::string& text);

/// Parses refuse|nearest-pd|isotropic (--information); throws UsageError otherwise.
[[nodiscard]] InformationRepair parseInformationRepair(const std::string& text);

/// A graph read from a file, with what came with it.
struct LoadedInput {
  Graph graph;
  std::string path;
  std::string format;                       ///< "g2o", "toro", "isam" or "npz"
  std::string description;                  ///< one line on what was read (for the user)
  std::vector<std::string> notes;           ///< further lines worth printing (model choice, ...)
  homework::PointGroundTruth ground_truth;  ///< empty unless the file has one
  /// .g2o: the file line of each edge, in graph edge order (io::LoadResult::edge_lines);
  /// empty for other formats.
  std::vector<std::size_t> edge_lines;
  /// The file's estimates are a deliberate initial guess that the tool's default
  /// initialisation must keep (.npz: the homework's); false for .g2o files, which get
  /// the global SE(2) initialisation by default.
  bool keep_initial_guess = false;
  /// Vertices created from edges (no line of the file defines them; their estimates are
  /// the types' defaults until an initialisation places them). A note says so.
  std::size_t created_vertices = 0;
};

/// Loads `path` as described above. Throws graphslam::InputError whose message holds
/// every diagnostic (`FILE:LINE: ...` for .g2o, `FILE: array 'NAME': ...` for .npz).
[[nodiscard]] LoadedInput loadInput(const std::string& path, const TypeRegistry& types,
                                    const InputOptions& options = {});

/// Parses auto|linear|bearing-range; throws UsageError otherwise.
[[nodiscard]] homework::PointObservationModel parseNpzModel(const std::string& text);

/// "created N vertices from edges (...)" for a graph with created vertices, else empty.
[[nodiscard]] std::string createdVerticesNote(const LoadedInput& in);

/// For a graph with vertices created from edges, which have no estimates of their own: the
/// global initialisation (SE(2) poses and landmarks), saying so; nothing otherwise.
void initializeCreatedVertices(const LoadedInput& in, Graph& graph, const SolverRegistry& solvers);

/// Checks an --init value (auto|global|none); throws UsageError otherwise.
void checkInitChoice(const std::string& init);

/// The tool's initial guess, as `optimize` makes it: `init` is auto (global for .g2o
/// inputs, the file's own estimates for inputs that keep theirs), global (SE(2)
/// orientations, then positions, by linear least squares, solved with the "auto" solver)
/// or none. Prints one line on what was done.
void applyInitialGuess(const LoadedInput& in, Graph& graph, std::string init,
                       const SolverRegistry& solvers);

}  // namespace graphslam::apps
