// SPDX-License-Identifier: MIT
// A plugin built only in the test tree: adds EDGE_SE2_RANGE, the distance between the
// positions of two SE(2) poses, unknown to the graphslam tool until loaded with --plugin,
// and the range-only and bearing-only landmark edges of the observability tests.
#include <Eigen/Core>

#include "../common/range_bearing_edges.h"
#include "graphslam/core/fixed_edge.h"
#include "graphslam/core/plugin.h"
#include "graphslam/types_slam2d/vertex_se2.h"

namespace {

using graphslam::types_slam2d::SE2;
using graphslam::types_slam2d::VertexSE2;

/// Range between two poses: e = |t_j - t_i| - z. Numeric Jacobian.
class EdgeSE2Range final : public graphslam::BaseBinaryEdge<1, double, VertexSE2, VertexSE2> {
 public:
  ErrorVector evaluate(const SE2& a, const SE2& b) const override {
    ErrorVector e;
    e[0] = (b.translation() - a.translation()).norm() - measurement();
    return e;
  }
};

}  // namespace

GRAPHSLAM_PLUGIN_ENTRY(host) {
  host.types->registerEdge<EdgeSE2Range>("EDGE_SE2_RANGE");
  graphslam::test::registerRangeBearingEdges(*host.types);
}
