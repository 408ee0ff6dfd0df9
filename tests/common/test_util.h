// SPDX-License-Identifier: MIT
// Shared helpers of the test suites.
#pragma once

#include <Eigen/Core>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "graphslam/core/edge.h"
#include "graphslam/core/graph.h"

namespace graphslam::test {

/// Directory of the public datasets: $GRAPHSLAM_DATA, else the configured default.
inline std::string dataDir() {
  if (const char* env = std::getenv("GRAPHSLAM_DATA"); env && *env) return env;
#ifdef GRAPHSLAM_DEFAULT_DATA_DIR
  return GRAPHSLAM_DEFAULT_DATA_DIR;
#else
  return "../shared/datasets";
#endif
}

inline bool fileExists(const std::string& path) { return std::ifstream(path).good(); }

/// Central-difference Jacobian of `edge` for slot `slot`, by perturbing the vertex in
/// place through its oplus (independent of the edge's own numeric default).
inline Eigen::MatrixXd numericJacobian(Edge& edge, Vertex& v, std::size_t /*slot*/,
                                       double h = 1e-6) {
  const int d = edge.dimension();
  Eigen::MatrixXd j(d, v.dimension());
  std::vector<double> delta(static_cast<std::size_t>(v.dimension()), 0.0);
  for (int k = 0; k < v.dimension(); ++k) {
    v.push();
    delta[k] = h;
    v.oplus(delta.data());
    edge.computeError();
    const Eigen::VectorXd ep = Eigen::Map<const Eigen::VectorXd>(edge.errorData(), d);
    v.pop();
    v.push();
    delta[k] = -h;
    v.oplus(delta.data());
    edge.computeError();
    const Eigen::VectorXd em = Eigen::Map<const Eigen::VectorXd>(edge.errorData(), d);
    v.pop();
    delta[k] = 0.0;
    j.col(k) = (ep - em) / (2 * h);
  }
  edge.computeError();
  return j;
}

/// Compares the edge's linearizeOplus() with numeric Jacobians for every vertex; returns
/// an empty string when they agree within `tol` (relative to max(1, |entry|)), else a
/// description of the first disagreeing entry.
inline std::string checkJacobians(Edge& edge, Graph& graph, double tol = 1e-6) {
  edge.computeError();
  edge.linearizeOplus();
  const int d = edge.dimension();
  for (std::size_t s = 0; s < edge.numVertices(); ++s) {
    Vertex& v = *graph.vertex(edge.vertexId(s));
    const Eigen::MatrixXd analytic =
        Eigen::Map<const Eigen::MatrixXd>(edge.jacobianData(s), d, v.dimension());
    const Eigen::MatrixXd numeric = numericJacobian(edge, v, s);
    for (int r = 0; r < d; ++r) {
      for (int c = 0; c < v.dimension(); ++c) {
        const double diff = std::abs(analytic(r, c) - numeric(r, c));
        if (diff > tol * std::max(1.0, std::abs(numeric(r, c)))) {
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

/// Checks that `statement` throws `Exception` whose message contains `fragment`.
#define EXPECT_THROW_MSG(statement, Exception, fragment)                                    \
  do {                                                                                      \
    try {                                                                                   \
      statement;                                                                            \
      ADD_FAILURE() << "no " #Exception " thrown by " #statement;                           \
    } catch (const Exception& e) {                                                          \
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << "got: " << e.what(); \
    }                                                                                       \
  } while (false)

}  // namespace graphslam::test
