// SPDX-License-Identifier: MIT
#include "graphslam/core/jacobian_check.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

namespace graphslam {

Eigen::MatrixXd numericJacobian(Edge& edge, Vertex& v, double step) {
  const int d = edge.dimension();
  Eigen::MatrixXd j(d, v.dimension());
  std::vector<double> delta(static_cast<std::size_t>(v.dimension()), 0.0);
  const auto errorAt = [&](std::size_t k, double h) {
    v.push();
    delta[k] = h;
    v.oplus(delta.data());
    edge.computeError();
    const Eigen::VectorXd e = Eigen::Map<const Eigen::VectorXd>(edge.errorData(), d);
    v.pop();
    delta[k] = 0.0;
    return e;
  };
  for (int k = 0; k < v.dimension(); ++k) {
    const auto col = static_cast<std::size_t>(k);
    j.col(k) = (errorAt(col, step) - errorAt(col, -step)) / (2 * step);
  }
  edge.computeError();
  return j;
}

std::string checkJacobians(Edge& edge, Graph& graph, double tolerance, double step) {
  edge.computeError();
  edge.linearizeOplus();
  const int d = edge.dimension();
  for (std::size_t s = 0; s < edge.numVertices(); ++s) {
    Vertex& v = *graph.vertex(edge.vertexId(s));
    const Eigen::MatrixXd analytic =
        Eigen::Map<const Eigen::MatrixXd>(edge.jacobianData(s), d, v.dimension());
    const Eigen::MatrixXd numeric = numericJacobian(edge, v, step);
    for (int r = 0; r < d; ++r) {
      for (int c = 0; c < v.dimension(); ++c) {
        const double diff = std::abs(analytic(r, c) - numeric(r, c));
        if (!(diff <= tolerance * std::max(1.0, std::abs(numeric(r, c))))) {
          std::ostringstream msg;
          msg << "slot " << s << " entry (" << r << "," << c << "): analytic " << analytic(r, c)
              << " numeric " << numeric(r, c);
          return msg.str();
        }
      }
    }
  }
  return {};
}

}  // namespace graphslam
