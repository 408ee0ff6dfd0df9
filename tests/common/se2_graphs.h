// SPDX-License-Identifier: MIT
// Building blocks of noise-free SE(2) test graphs.
#pragma once

#include <memory>
#include <vector>

#include "graphslam/core/graph.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/se2.h"

namespace graphslam::test {

/// Adds the EDGE_SE2 from pose i to pose j that measures exactly truth[i]^-1 truth[j].
inline void addExactSE2Edge(Graph& g, const std::vector<types_slam2d::SE2>& truth, int i, int j) {
  auto e = std::make_unique<types_slam2d::EdgeSE2>();
  e->setVertexIds({i, j});
  e->setMeasurement(truth[i].inverse() * truth[j]);
  g.addEdge(std::move(e));
}

}  // namespace graphslam::test
