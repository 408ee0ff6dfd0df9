// SPDX-License-Identifier: MIT
#include "graphslam/simulation/wrong_loop_closures.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <set>
#include <utility>

#include "graphslam/support/error.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/vertex_se2.h"

namespace graphslam::simulation {

using namespace graphslam::types_slam2d;

namespace {

constexpr double kPi = 3.14159265358979323846;

/// Portable draws from a std::mt19937_64 (whose output sequence the standard fixes; the
/// standard distributions' algorithms are left to each library).
class Draw {
 public:
  explicit Draw(std::uint64_t seed) : rng_(seed) {}
  /// Uniform in [0, 1) with 53 random bits.
  double unit() { return static_cast<double>(rng_() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * unit(); }
  /// Uniform in [0, n), n > 0, by rejection (no modulo bias).
  std::size_t index(std::size_t n) {
    const std::uint64_t range = static_cast<std::uint64_t>(n);
    const std::uint64_t limit = std::numeric_limits<std::uint64_t>::max() -
                                std::numeric_limits<std::uint64_t>::max() % range;
    std::uint64_t x;
    do x = rng_();
    while (x >= limit);
    return static_cast<std::size_t>(x % range);
  }

 private:
  std::mt19937_64 rng_;
};

std::pair<VertexId, VertexId> ordered(VertexId a, VertexId b) {
  return a < b ? std::make_pair(a, b) : std::make_pair(b, a);
}

bool isLoopClosure(const EdgeSE2& e) {
  const VertexId a = e.vertexId(0), b = e.vertexId(1);
  return (a > b ? a - b : b - a) > 1;
}

/// Half the larger side of the bounding box of the poses' positions.
double halfExtent(const std::vector<const VertexSE2*>& poses) {
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (const VertexSE2* v : poses) {
    lo = lo.cwiseMin(v->estimate().translation());
    hi = hi.cwiseMax(v->estimate().translation());
  }
  return 0.5 * (hi - lo).maxCoeff();
}

}  // namespace

WrongLoopClosures addWrongLoopClosures(Graph& graph, const WrongLoopClosureOptions& options) {
  std::vector<const VertexSE2*> poses;
  for (const auto& [id, v] : graph.vertices()) {
    if (const auto* p = dynamic_cast<const VertexSE2*>(v.get())) poses.push_back(p);
  }
  std::set<std::pair<VertexId, VertexId>> joined;
  std::vector<const EdgeSE2*> se2, closures;
  for (const auto& e : graph.edges()) {
    if (e->vertexIds().size() == 2) joined.insert(ordered(e->vertexId(0), e->vertexId(1)));
    if (const auto* s = dynamic_cast<const EdgeSE2*>(e.get())) {
      se2.push_back(s);
      if (isLoopClosure(*s)) closures.push_back(s);
    }
  }
  if (poses.size() < 3 || se2.empty()) {
    throw Error(
        "adding wrong loop closures needs a 2D pose graph (at least 3 VERTEX_SE2 and an "
        "EDGE_SE2); this one has " +
        std::to_string(poses.size()) + " VERTEX_SE2 and " + std::to_string(se2.size()) +
        " EDGE_SE2");
  }
  WrongLoopClosures out;
  out.loop_closures = closures.size();
  out.requested = options.count >= 0
                      ? static_cast<std::size_t>(options.count)
                      : static_cast<std::size_t>(
                            std::llround(options.fraction * static_cast<double>(closures.size())));
  const double range = options.translation_range > 0
                           ? options.translation_range
                           : std::max(options.min_translation_range, halfExtent(poses));
  const std::vector<const EdgeSE2*>& info_sources = closures.empty() ? se2 : closures;
  Draw draw(options.seed);
  for (std::size_t k = 0; k < out.requested; ++k) {
    bool found = false;
    VertexId a = 0, b = 0;
    for (int attempt = 0; attempt < options.max_attempts_per_edge && !found; ++attempt) {
      a = poses[draw.index(poses.size())]->id();
      b = poses[draw.index(poses.size())]->id();
      found = (a > b ? a - b : b - a) > 1 && joined.count(ordered(a, b)) == 0;
    }
    if (!found) break;
    joined.insert(ordered(a, b));
    const double x = draw.uniform(-range, range);
    const double y = draw.uniform(-range, range);
    const double theta = draw.uniform(-kPi, kPi);
    const EdgeSE2* like = info_sources[draw.index(info_sources.size())];
    auto e = std::make_unique<EdgeSE2>();
    e->setVertexIds({a, b});
    e->setMeasurement(SE2(x, y, theta));
    e->setInformation(like->information());
    graph.addEdge(std::move(e));
    out.edge_indices.push_back(graph.numEdges() - 1);
  }
  return out;
}

}  // namespace graphslam::simulation
