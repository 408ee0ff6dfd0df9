// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "graphslam/core/graph.h"

namespace graphslam::simulation {

/// How addWrongLoopClosures corrupts a 2D pose graph. A loop closure is an EDGE_SE2
/// between two poses whose ids differ by more than one (odometry joins consecutive ids);
/// outlier fractions are counted against them, as in the GNC papers (Yang et al. 2020,
/// Carlone's benchmarks: "10 % outliers" = one wrong closure per ten right ones).
struct WrongLoopClosureOptions {
  /// Wrong closures to add as a fraction of the graph's loop closures (rounded to the
  /// nearest integer)...
  double fraction = 0.1;
  /// ...unless this is >= 0: then exactly this many.
  long count = -1;
  /// Seed of the generator (std::mt19937_64 with our own integer-to-double conversion,
  /// so a seed gives the same edges on every standard library).
  std::uint64_t seed = 1;
  /// Each translation component of a measurement is uniform in [-r, r] with r this (m)
  /// when > 0; 0: half the larger side of the bounding box of the poses' estimates (at
  /// least min_translation_range), so the measurement is of the graph's scale.
  double translation_range = 0.0;
  double min_translation_range = 1.0;
  /// Attempts per wanted edge at drawing a pose pair that is neither odometry nor already
  /// joined before giving up (a dense graph may have too few free pairs).
  int max_attempts_per_edge = 1000;
};

/// What addWrongLoopClosures added.
struct WrongLoopClosures {
  /// Indices into graph.edges() of the added edges, in the order added (they are
  /// appended after the existing edges).
  std::vector<std::size_t> edge_indices;
  std::size_t loop_closures = 0;  ///< right (existing) loop closures counted
  std::size_t requested = 0;      ///< how many were asked for (fewer added when pairs ran out)
};

/// Appends random wrong loop closures to `graph`: EDGE_SE2 between two distinct VERTEX_SE2
/// drawn uniformly whose ids differ by more than one and which no edge joins yet, with
/// a measurement uniform in translation (see translation_range) and angle ([-pi, pi)), and
/// the information of an existing loop closure drawn at random (of an existing EDGE_SE2
/// when there is none), so it looks like a real one. Deterministic for a given seed and
/// graph. Throws graphslam::Error when the graph has fewer than three poses or no EDGE_SE2.
[[nodiscard]] WrongLoopClosures addWrongLoopClosures(Graph& graph,
                                                     const WrongLoopClosureOptions& options);

}  // namespace graphslam::simulation
