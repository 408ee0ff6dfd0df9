// SPDX-License-Identifier: MIT
// H = sum J^T Omega J assembled independently of the library's Hessian structure, for
// checking marginal covariances.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <map>
#include <vector>

#include "graphslam/core/graph.h"

namespace graphslam::test {

/// Full symmetric H over the non-fixed vertices with edges (columns in id order), from
/// every edge's Jacobians at the current estimates.
struct HessianReference {
  std::map<VertexId, int> column;
  Eigen::SparseMatrix<double> h;

  explicit HessianReference(Graph& g) {
    int n = 0;
    for (const auto& [id, v] : g.vertices()) {
      if (v->fixed() || v->edges().empty()) continue;
      column[id] = n;
      n += v->dimension();
    }
    std::vector<Eigen::Triplet<double>> triplets;
    for (const auto& e : g.edges()) {
      e->computeError();
      e->linearizeOplus();
      const int d = e->dimension();
      const Eigen::Map<const Eigen::MatrixXd> omega(e->informationData(), d, d);
      for (std::size_t a = 0; a < e->numVertices(); ++a) {
        for (std::size_t b = 0; b < e->numVertices(); ++b) {
          const Vertex* va = e->vertex(a);
          const Vertex* vb = e->vertex(b);
          if (va->fixed() || vb->fixed()) continue;
          const Eigen::Map<const Eigen::MatrixXd> ja(e->jacobianData(a), d, va->dimension());
          const Eigen::Map<const Eigen::MatrixXd> jb(e->jacobianData(b), d, vb->dimension());
          const Eigen::MatrixXd block = ja.transpose() * omega * jb;
          for (int r = 0; r < block.rows(); ++r) {
            for (int c = 0; c < block.cols(); ++c) {
              triplets.emplace_back(column.at(va->id()) + r, column.at(vb->id()) + c, block(r, c));
            }
          }
        }
      }
    }
    h.resize(n, n);
    h.setFromTriplets(triplets.begin(), triplets.end());
  }
};

}  // namespace graphslam::test
