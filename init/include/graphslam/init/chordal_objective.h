// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <vector>

#include "graphslam/core/graph.h"

namespace graphslam::init {

/// The graph's relative-pose edges switched to SE-Sync's objective (Rosen et al., IJRR
/// 2019, Problem 1): every active EDGE_SE2 and EDGE_SE3:QUAT is left inactive and a chordal
/// edge (EdgeSE2Chordal, EdgeSE3Chordal) with SE-Sync's weights takes its place:
///   SE(2): tau = 2 / tr(Omega_t^-1), kappa = Omega_theta;
///   SE(3): tau = 3 / tr(Omega_t^-1), kappa = 3 / (2 tr(Omega_R^-1)).
/// The optimizer's chi2 is then SE-Sync's f (no 1/2). restore() takes the chordal edges
/// out again and reactivates the originals (before writing the graph: the chordal edges
/// have no `.g2o` tag).
class ChordalObjective {
 public:
  /// Switches `graph`; the graph must outlive this object's use.
  explicit ChordalObjective(Graph& graph);
  ChordalObjective(const ChordalObjective&) = delete;
  ChordalObjective& operator=(const ChordalObjective&) = delete;
  ~ChordalObjective() { restore(); }

  /// Edges switched (2D and 3D together).
  [[nodiscard]] std::size_t switched() const { return chordal_.size(); }
  /// Edges whose information gave no positive finite weight (left as they were).
  [[nodiscard]] std::size_t skipped() const { return skipped_; }
  /// SE-Sync's f at the current estimates (the chordal edges' chi2).
  [[nodiscard]] double value() const;
  /// Back to the original edges; idempotent.
  void restore();

 private:
  Graph* graph_;
  std::vector<Edge*> originals_;
  std::vector<Edge*> chordal_;
  std::size_t skipped_ = 0;
};

}  // namespace graphslam::init
