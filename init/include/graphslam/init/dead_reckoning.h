// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/core/graph.h"
#include "graphslam/io/trajectory.h"

namespace graphslam::init {

/// Odometry chain of an SE(2) graph: its poses (VERTEX_SE2) in id order, other vertices
/// such as landmarks skipped, each composed from the one before by an EDGE_SE2 joining the
/// two (in either direction), from the estimate of the lowest pose id. Throws
/// graphslam::Error naming the two poses when no edge joins a consecutive pair.
[[nodiscard]] io::Trajectory deadReckonGraph(const Graph& graph);

}  // namespace graphslam::init
