// SPDX-License-Identifier: MIT
// Checks every edge type of every module must pass: analytic Jacobians against numeric
// ones, and an exact .g2o write/read round trip.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "graphslam/core/type_registry.h"
#include "graphslam/io/g2o.h"
#include "test_util.h"

namespace graphslam::test {

/// For `trials` graphs made by `make(graph, rng)` (returning the edge of type E to check),
/// compares the analytic Jacobians with central differences through the vertices' oplus
/// (checkJacobians) and with the base's numeric default (differences on copies of the
/// estimates, what a type without linearizeOplus() gets).
template <typename E, typename Make>
void expectAnalyticJacobians(Make make, unsigned seed, int trials) {
  std::mt19937 rng(seed);
  int near_wrap = 0;
  for (int trial = 0; trial < trials; ++trial) {
    Graph g;
    E* e = make(g, rng);
    // An angular error within a step of +-pi wraps between the two central differences:
    // the numeric derivative is meaningless there (which trials land there depends on the
    // compiler's rounding), so such a trial is drawn again.
    e->computeError();
    const Eigen::Map<const Eigen::VectorXd> error(e->errorData(), e->dimension());
    if ((error.array().abs() - 3.14159265358979323846).abs().minCoeff() < 1e-4) {
      ASSERT_LT(++near_wrap, trials / 10 + 1) << "too many trials at the angle wrap";
      --trial;
      continue;
    }
    const std::string problem = checkJacobians(*e, g, 1e-6);
    ASSERT_TRUE(problem.empty()) << "trial " << trial << ": " << problem;
    e->computeError();
    e->linearizeOplus();
    std::vector<Eigen::MatrixXd> analytic;
    for (std::size_t s = 0; s < e->numVertices(); ++s) {
      analytic.emplace_back(Eigen::Map<const Eigen::MatrixXd>(e->jacobianData(s), e->dimension(),
                                                              e->vertex(s)->dimension()));
    }
    e->numericJacobians();
    for (std::size_t s = 0; s < e->numVertices(); ++s) {
      const Eigen::Map<const Eigen::MatrixXd> numeric(e->jacobianData(s), e->dimension(),
                                                      e->vertex(s)->dimension());
      ASSERT_LT((numeric - analytic[s]).cwiseAbs().maxCoeff(),
                1e-6 * std::max(1.0, analytic[s].cwiseAbs().maxCoeff()))
          << "trial " << trial << ", numeric default, slot " << s;
    }
  }
}

/// Flat data of a vertex or edge through one of its get*Data functions.
template <typename Get>
std::vector<double> flatData(int n, Get get) {
  std::vector<double> v(static_cast<std::size_t>(n));
  get(v.data());
  return v;
}

/// Writes `g` (one edge and its vertices) as .g2o, reads it back through `types` and
/// expects the same estimates, parameters, measurement, information and chi2, exactly.
inline void expectExactRoundTrip(Graph& g, const TypeRegistry& types) {
  ASSERT_EQ(g.numEdges(), 1u);
  const Edge& e = *g.edges()[0];
  ASSERT_NE(types.tagOf(e), nullptr) << "type not registered";
  std::stringstream text;
  io::writeG2o(text, g, types);
  auto loaded = io::readG2o(text, "roundtrip", types);
  ASSERT_TRUE(loaded.ok()) << loaded.diagnostics.at(0).str() << "\n" << text.str();
  ASSERT_EQ(loaded.graph.numEdges(), 1u);
  ASSERT_EQ(loaded.graph.numVertices(), g.numVertices());
  const Edge& back = *loaded.graph.edges()[0];
  EXPECT_EQ(
      flatData(e.measurementDataDimension(), [&](double* d) { e.getMeasurementData(d); }),
      flatData(back.measurementDataDimension(), [&](double* d) { back.getMeasurementData(d); }));
  EXPECT_EQ(flatData(e.parameterDataDimension(), [&](double* d) { e.getParameterData(d); }),
            flatData(back.parameterDataDimension(), [&](double* d) { back.getParameterData(d); }));
  const int d = e.dimension();
  for (int i = 0; i < d * d; ++i) EXPECT_EQ(e.informationData()[i], back.informationData()[i]);
  for (const auto& entry : g.vertices()) {
    const VertexId id = entry.first;
    const Vertex* v = entry.second.get();  // not a structured binding: lambdas capture it
    const Vertex& w = *loaded.graph.vertex(id);
    EXPECT_EQ(flatData(v->estimateDataDimension(), [&](double* x) { v->getEstimateData(x); }),
              flatData(w.estimateDataDimension(), [&](double* x) { w.getEstimateData(x); }))
        << "vertex " << id;
    EXPECT_EQ(flatData(v->parameterDataDimension(), [&](double* x) { v->getParameterData(x); }),
              flatData(w.parameterDataDimension(), [&](double* x) { w.getParameterData(x); }))
        << "vertex " << id;
  }
  EXPECT_NEAR(loaded.graph.chi2(), g.chi2(), 1e-12 * std::max(1.0, g.chi2()));
}

}  // namespace graphslam::test
