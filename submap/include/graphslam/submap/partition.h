// SPDX-License-Identifier: MIT
// A graph's variables split into submaps joined by separator vertices.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "graphslam/core/graph.h"

namespace graphslam::submap {

/// How partitionGraph splits a graph.
struct PartitionOptions {
  /// How the vertices are split.
  enum class Method {
    /// Recursive node bisection by METIS (METIS_ComputeVertexSeparator through CHOLMOD's
    /// Partition module): each cut is a small vertex separator of the part it splits. Needs
    /// the build with SuiteSparse; partitionGraph throws graphslam::Error without it.
    node_bisection,
    /// Recursive bisection of breadth-first orders (each part split at the median distance
    /// from a peripheral vertex), then a cover of the cut edges. No dependency; larger
    /// separators on maps with many loop closures.
    breadth_first,
  };
  /// node_bisection when the build has CHOLMOD's Partition module, else breadth_first.
  static Method defaultMethod();
  Method method = defaultMethod();
  /// Submaps (>= 1). Bisection halves a part's vertices at every level: with a power of two
  /// the submaps hold about the same number of vertices; otherwise a part of p submaps is
  /// split into floor(p/2) and ceil(p/2) submaps of equal halves, so some submaps hold up to
  /// twice as many vertices as others.
  int num_submaps = 4;
  /// Refused (graphslam::Error) when the separator holds more than this fraction of the
  /// optimised vertices: the separator system would be about as large as the whole one, so
  /// the submaps buy nothing (a graph with one densely connected component and no small
  /// separator for this many submaps).
  double max_separator_fraction = 0.3;
  /// Refused when one submap touches separator variables of more than this many dimensions:
  /// its separator block is dense (dimension^2 doubles; 8000 is 512 MB).
  int max_submap_separator_dimension = 8000;
};

/// One submap: the vertices only it optimises (its interior), the separator vertices its
/// edges touch, and its edges. Each active edge belongs to exactly one submap; an edge's
/// non-fixed vertices are interior vertices of that submap or separator vertices.
struct Submap {
  std::vector<Vertex*> interior;  ///< by increasing id
  std::vector<int> separators;    ///< indices into Partition::separators, increasing
  std::vector<Edge*> edges;       ///< in graph order
  int interior_dimension = 0;     ///< sum of the interior vertices' dimensions
  int separator_dimension = 0;    ///< sum of dimensions of `separators`
};

/// The split of a graph's optimised vertices (non-fixed, with an active edge).
struct Partition {
  std::vector<Submap> submaps;
  /// The separator vertices, by increasing id; separator_offsets[k] is the first column of
  /// separators[k] in the separator system (one more entry: its dimension).
  std::vector<Vertex*> separators;
  std::vector<int> separator_offsets;
  std::size_t num_variables = 0;  ///< optimised vertices
  int dimension = 0;              ///< their total dimension
  /// One line: submaps, vertices, largest submap, separator size.
  [[nodiscard]] std::string describe() const;
};

/// Splits the optimised vertices into options.num_submaps parts by recursive bisection
/// (PartitionOptions::Method): node bisection makes the vertices of each cut separator
/// vertices; breadth-first bisection cuts at the median distance from a peripheral vertex
/// (a level set of the graph) and then covers the edges that join parts with separator
/// vertices. Deterministic: the same graph gives the same partition (MPI ranks rely on it).
/// Throws graphslam::Error naming the sizes when the separator is too large
/// (PartitionOptions), and when a submap holds a group of interior vertices that nothing
/// anchors (no separator vertex, fixed vertex or unary edge among their edges: the gauge of
/// a component of the graph is free; SubmapSolver fixes it first, as the Optimizer does).
[[nodiscard]] Partition partitionGraph(const Graph& graph, const PartitionOptions& options);

}  // namespace graphslam::submap
