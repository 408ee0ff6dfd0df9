// SPDX-License-Identifier: MIT
#pragma once

#include <string>
#include <vector>

#include "graphslam/core/graph.h"
#include "graphslam/core/linear_solver.h"

namespace graphslam::init {

/// What initializeGraph did, in lines a program may print ("global, 1227 poses and 0
/// landmarks placed in 0.0021 s", "no EDGE_SE2 or EDGE_SE3:QUAT in the graph: nothing to
/// initialise").
struct InitialGuessReport {
  std::size_t poses = 0;      ///< poses placed (2D and 3D)
  std::size_t landmarks = 0;  ///< landmarks placed
  std::vector<std::string> lines;
};

/// The global initial guess of a graph: the SE(2) initialisation (initializeGlobal:
/// orientations, then positions, by linear least squares) of its EDGE_SE2 part and the
/// chordal SE(3) one (initializeChordal3d) of its EDGE_SE3:QUAT part, their linear systems
/// solved by `solver` of `solvers` ("auto": the default solver's choice of ordering and
/// backend, which large graphs need). Edges of other types (custom ones among them) do not
/// take part; vertices they alone reach keep their estimates, and the report says so.
[[nodiscard]] InitialGuessReport initializeGraph(Graph& graph, const SolverRegistry& solvers,
                                                 const std::string& solver = "auto");

}  // namespace graphslam::init
