// SPDX-License-Identifier: MIT
// Builds a unit square of four SE(2) poses from a rough guess, optimises it and prints the final
// chi2.
#include <graphslam/core/optimizer.h>
#include <graphslam/solvers/register.h>
#include <graphslam/types_slam2d/edge_se2.h>
#include <graphslam/types_slam2d/register.h>
#include <graphslam/types_slam2d/vertex_se2.h>

#include <cstdio>
#include <memory>

int main() {
  using namespace graphslam;
  using namespace graphslam::types_slam2d;
  SolverRegistry solvers;
  solvers::registerSolvers(solvers);
  Graph graph;
  const SE2 guess[4] = {SE2(0, 0, 0), SE2(1.1, 0.1, 1.5), SE2(0.9, 1.1, 3.2), SE2(-0.1, 0.9, 4.6)};
  for (int i = 0; i < 4; ++i) {
    auto v = std::make_unique<VertexSE2>();
    v->setId(i);
    v->setEstimate(guess[i]);
    graph.addVertex(std::move(v));
  }
  for (int i = 0; i < 4; ++i) {
    auto e = std::make_unique<EdgeSE2>();
    e->setVertexIds({i, (i + 1) % 4});
    e->setMeasurement(SE2(1, 0, 1.5707963267948966));
    graph.addEdge(std::move(e));
  }
  Optimizer optimizer(graph, solvers);
  const Summary s = optimizer.optimize();
  std::printf("consumer: %s, chi2 %.3e\n", toString(s.status), s.final_chi2);
  return s.final_chi2 < 1e-12 ? 0 : 1;
}
