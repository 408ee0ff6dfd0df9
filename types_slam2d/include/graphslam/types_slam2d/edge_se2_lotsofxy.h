// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <string>

#include "graphslam/core/base_multi_edge.h"
#include "graphslam/types_slam2d/se2.h"

namespace graphslam::types_slam2d {

/// Any number n >= 1 of landmarks l_1..l_n observed together from pose X — `.g2o` tag
/// EDGE_SE2_LOTSOFXY. Vertices: the pose (VERTEX_SE2), then the points (VERTEX_XY).
/// Line (the one g2o writes; Edge::separatedCount):
///   `EDGE_SE2_LOTSOFXY pose p_1 ... p_n || n z_1x z_1y ... z_nx z_ny`, then the upper
///   triangle of the 2n x 2n information.
/// The measurement is a vector of 2n values, sized with the vertices (setVertexIds).
/// Error (g2o's convention): e = [R^T (l_1 - t) - z_1; ...; R^T (l_n - t) - z_n].
/// Analytic Jacobians w.r.t. the vertices' updates.
class EdgeSE2LotsOfXY final : public BaseMultiEdge<Eigen::Dynamic, Eigen::VectorXd> {
 public:
  /// The number of points, n.
  [[nodiscard]] int separatedCount(std::size_t num_vertices) const override {
    return num_vertices > 0 ? static_cast<int>(num_vertices) - 1 : 0;
  }
  void computeError() override;
  void linearizeOplus() override;
  [[nodiscard]] bool acceptsVertex(std::size_t slot, const Vertex& v) const override;
  [[nodiscard]] std::string expectedVertexType(std::size_t slot) const override;

 protected:
  /// 2 error rows and measurement values per point; throws graphslam::Error without a point.
  void resizeForVertices(std::size_t num_vertices) override;
};

}  // namespace graphslam::types_slam2d
