// SPDX-License-Identifier: MIT
// The observability check of `optimize` and `info` (core's checkObservability): which
// vertices the edges do not determine, named with the reason and their edges' file lines.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "graphslam/core/graph.h"
#include "graphslam/core/type_registry.h"
#include "graphslam/diagnostics/observability.h"
#include "graphslam/optimizer/optimizer.h"
#include "input.h"

namespace graphslam::apps {

/// The check before solving. Every vertex determined: prints the information on unanchored
/// components (unless `quiet`) and returns true. Otherwise, with `drop`, removes the
/// undetermined vertices and their edges (keeping in.edge_lines in step), says how many and
/// which, checks again (a removal may leave a vertex without edges) and returns true;
/// without `drop`, prints the list to stderr and returns false: the caller exits 2 before
/// iterating and writes nothing.
[[nodiscard]] bool checkBeforeSolving(LoadedInput& in, const TypeRegistry& types, bool drop,
                                      int threads, bool quiet);

/// After a successful run in which no iteration factorised the undamped H (IterationStats::
/// undamped: Levenberg-Marquardt, a fallback after a failed Gauss-Newton step, regularised
/// dogleg steps; damping hides a singular H): factorises H at the result once
/// (MarginalCovariance, whose failure names the vertex). Returns true when H is positive
/// definite or an iteration already showed it; otherwise prints the
/// vertex, its edges' file lines and why to stderr and returns false: the estimate of those
/// vertices is arbitrary, and the caller exits 1 writing nothing.
[[nodiscard]] bool checkUndampedAtResult(LoadedInput& in, const Summary& summary,
                                         const SolverRegistry& solvers);

/// `info`: prints the report (a list, not a failure).
void printObservability(LoadedInput& in, const TypeRegistry& types);

/// "line 12" / "lines 12, 40, ..." for edges given as indices into the graph's edges, when
/// `edge_lines` maps them all (a .g2o input, edge_lines.size() == num_edges, no edge added
/// since); empty otherwise.
[[nodiscard]] std::string edgeLines(const std::vector<std::size_t>& edges,
                                    const std::vector<std::size_t>& edge_lines,
                                    std::size_t num_edges);

/// Before the initial guess: whether every edge's term is finite at the input's estimates.
/// If not, reports the first edge that is not (its vertices, its line, why: a measurement
/// or information too large for double arithmetic) as the optimizer would, and returns
/// false; initialising from such an edge would spread the overflow to every vertex.
[[nodiscard]] bool checkFiniteTerms(LoadedInput& in, const std::string& output);

/// "that edge is on line N of INPUT\n" for the edge a failed optimisation names
/// (Summary::failed_edge, an index into the graph's edges; -1: none), or empty.
[[nodiscard]] std::string failedEdgeNote(std::ptrdiff_t failed_edge,
                                         const std::vector<std::size_t>& edge_lines,
                                         std::size_t num_edges, const std::string& input);

}  // namespace graphslam::apps
