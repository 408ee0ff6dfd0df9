// SPDX-License-Identifier: MIT
// A plugin built with the package's graphslam_add_plugin(): one edge type of its own.
#include <graphslam/core/fixed_edge.h>
#include <graphslam/core/plugin.h>
#include <graphslam/types_slam2d/vertex_xy.h>

namespace {
/// A prior on a 2D point: e = x - z.
class EdgeConsumerPrior final
    : public graphslam::BaseUnaryEdge<2, Eigen::Vector2d, graphslam::types_slam2d::VertexXY> {
 public:
  [[nodiscard]] ErrorVector evaluate(const Eigen::Vector2d& x) const override {
    return x - measurement();
  }
};
}  // namespace

GRAPHSLAM_PLUGIN_ENTRY(host) { host.types->registerEdge<EdgeConsumerPrior>("EDGE_CONSUMER_PRIOR"); }
