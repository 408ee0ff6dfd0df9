// SPDX-License-Identifier: MIT
// Checking an edge type's analytic Jacobians against numeric ones: what every edge of the
// library is tested with, for the authors of new edge types (C++ plugins and tests).
#pragma once

#include <Eigen/Core>
#include <string>

#include "graphslam/core/edge.h"
#include "graphslam/core/graph.h"

namespace graphslam {

/// The Jacobian of `edge`'s error with respect to vertex `v` (one of its vertices) by
/// central differences through the vertex's update (its oplus: the derivative an analytic
/// linearizeOplus() must match), perturbing the estimate in place and restoring it.
[[nodiscard]] Eigen::MatrixXd numericJacobian(Edge& edge, Vertex& v,
                                              double step = kNumericJacobianStep);

/// Compares `edge`'s linearizeOplus() with numericJacobian() for every vertex of the edge
/// (in `graph`, at their current estimates). Empty when every entry agrees within
/// `tolerance` relative to max(1, |numeric entry|); else a description of the first entry
/// that does not: "slot S entry (R,C): analytic A numeric N".
[[nodiscard]] std::string checkJacobians(Edge& edge, Graph& graph, double tolerance = 1e-6,
                                         double step = kNumericJacobianStep);

}  // namespace graphslam
