// SPDX-License-Identifier: MIT
// compareWithBatch: a graph's estimates against the batch optimizer's on a copy.
#include <algorithm>
#include <cmath>
#include <vector>

#include "graphslam/core/graph_copy.h"
#include "graphslam/incremental/replay.h"

namespace graphslam::incremental {

namespace {

/// Largest |a - b| over the flat estimate data, each difference taken modulo 2 pi too
/// (an angle wrapped to the other end of its range is the same angle).
double estimateDifference(const Vertex& a, const Vertex& b) {
  const std::size_t n = static_cast<std::size_t>(a.estimateDataDimension());
  std::vector<double> x(n), y(n);
  a.getEstimateData(x.data());
  b.getEstimateData(y.data());
  constexpr double kTwoPi = 2.0 * M_PI;
  double largest = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const double d = x[k] - y[k];
    const double wrapped = d - kTwoPi * std::round(d / kTwoPi);
    largest = std::max(largest, std::min(std::abs(d), std::abs(wrapped)));
  }
  return largest;
}

}  // namespace

BatchComparison compareWithBatch(const Graph& graph, const TypeRegistry& types,
                                 const SolverRegistry& solvers, const Optimizer::Options& options) {
  Graph copy = copyGraph(graph, types);
  BatchComparison c;
  {
    Optimizer optimizer(copy, solvers, options);
    c.summary = optimizer.optimize();
  }
  c.chi2 = c.summary.initial_cost;
  c.batch_chi2 = c.summary.final_cost;
  c.relative_gap = c.batch_chi2 != 0.0 ? (c.chi2 - c.batch_chi2) / c.batch_chi2 : c.chi2;
  for (const auto& [id, v] : graph.vertices()) {
    const double d = estimateDifference(*v, *copy.vertex(id));
    if (d > c.max_difference || c.worst_vertex < 0) {
      c.max_difference = d;
      c.worst_vertex = id;
    }
  }
  return c;
}

}  // namespace graphslam::incremental
