// SPDX-License-Identifier: MIT
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "graphslam/core/fixed_edge.h"
#include "graphslam/core/jacobian_check.h"
#include "graphslam/types_slam2d/vertex_xy.h"

using namespace graphslam;

namespace {

/// A unary edge e = |x|^2 - measurement on a 2D point, with a right or a wrong analytic
/// Jacobian (the factor 2 forgotten).
class SquaredNormEdge final : public BaseUnaryEdge<1, double, types_slam2d::VertexXY> {
 public:
  explicit SquaredNormEdge(bool right) : right_(right) {}
  [[nodiscard]] ErrorVector evaluate(const Eigen::Vector2d& x) const override {
    return ErrorVector(x.squaredNorm() - measurement());
  }
  void linearizeOplus() override {
    const Eigen::Vector2d& x = vertexXi<0>().estimate();
    jacobian<0>() = (right_ ? 2.0 : 1.0) * x.transpose();
  }

 private:
  bool right_;
};

}  // namespace

// The check plugin authors use (graphslam/core/jacobian_check.h) passes a right Jacobian
// and names the first entry of a wrong one.
TEST(Core_JacobianCheck, NamesTheFirstWrongEntry) {
  for (const bool right : {true, false}) {
    Graph g;
    auto v = std::make_unique<types_slam2d::VertexXY>();
    v->setId(0);
    v->setEstimate(Eigen::Vector2d(0.5, -2.0));
    g.addVertex(std::move(v));
    auto e = std::make_unique<SquaredNormEdge>(right);
    e->setVertexIds({0});
    e->setMeasurement(1.0);
    e->setInformation(Eigen::Matrix<double, 1, 1>::Identity());
    SquaredNormEdge* edge = e.get();
    g.addEdge(std::move(e));
    const std::string problem = checkJacobians(*edge, g);
    if (right) {
      EXPECT_EQ(problem, "");
      const Eigen::MatrixXd j = numericJacobian(*edge, *g.vertex(0));
      EXPECT_NEAR(j(0, 0), 1.0, 1e-8);
      EXPECT_NEAR(j(0, 1), -4.0, 1e-8);
    } else {
      EXPECT_EQ(problem, "slot 0 entry (0,0): analytic 0.5 numeric 1");
    }
  }
}
