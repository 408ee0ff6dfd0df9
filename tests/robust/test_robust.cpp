// SPDX-License-Identifier: MIT
// Robust kernels: derivatives, weights and shape of every kernel; registry and spec errors;
// edge selection; their effect on a small SE(2) graph with one wrong loop closure.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "graphslam/optimizer/optimizer.h"
#include "graphslam/robust/apply.h"
#include "graphslam/robust/kernels.h"
#include "graphslam/robust/register.h"
#include "graphslam/solvers/register.h"
#include "graphslam/support/error.h"
#include "graphslam/types_slam2d/edge_prior_se2.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/edge_se2_xy.h"
#include "graphslam/types_slam2d/register.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"

namespace {

using namespace graphslam;
using namespace graphslam::types_slam2d;

const std::vector<std::string> kKernelNames = {
    "cauchy",       "dcs",       "fair", "geman-mcclure", "huber",
    "pseudo-huber", "saturated", "tls",  "tukey",         "welsch"};

/// The kernels (registered as the robust module) and the slam2d types.
struct Registries {
  TypeRegistry types;
  KernelRegistry kernels;
};

Registries kernelRegistry() {
  Registries r;
  r.kernels.setOrigin("robust");
  robust::registerKernels(r.kernels);
  types_slam2d::registerTypes(r.types);
  return r;
}

/// Where a piecewise kernel switches branch (rho'' jumps there): width^2, phi for dcs.
double kink(const std::string& name, double width) { return name == "dcs" ? width : width * width; }

struct Rho {
  double v[3];
};

Rho eval(const RobustKernel& k, double s) {
  Rho r{};
  k.robustify(s, r.v);
  return r;
}

/// Squared errors from tiny to huge, relative to the kink, avoiding the kink itself.
std::vector<double> samplePoints(double knee) {
  std::vector<double> s;
  for (double f : {1e-6, 1e-3, 0.05, 0.3, 0.7, 0.9, 0.99, 1.01, 1.1, 1.5, 3.0, 10.0, 100.0, 1e4}) {
    s.push_back(f * knee);
  }
  return s;
}

class RobustKernels : public ::testing::TestWithParam<std::string> {
 protected:
  KernelRegistry registry_ = kernelRegistry().kernels;
};

TEST_P(RobustKernels, DerivativesMatchCentralDifferences) {
  for (double width : {0.5, 1.0, robust::kDefaultWidth, 7.0}) {
    const auto kernel = registry_.create(GetParam(), width);
    const double knee = kink(GetParam(), width);
    for (double s : samplePoints(knee)) {
      const double h = 1e-5 * s;
      const Rho lo = eval(*kernel, s - h), mid = eval(*kernel, s), hi = eval(*kernel, s + h);
      const double d1 = (hi.v[0] - lo.v[0]) / (2 * h);
      const double d2 = (hi.v[1] - lo.v[1]) / (2 * h);
      SCOPED_TRACE("width " + std::to_string(width) + ", s " + std::to_string(s));
      EXPECT_NEAR(mid.v[1], d1, 1e-6 * std::max(1.0, std::abs(d1)));
      EXPECT_NEAR(mid.v[2], d2, 1e-5 * std::max(1.0 / knee, std::abs(d2)));
    }
  }
}

TEST_P(RobustKernels, ZeroAtZeroUnitSlopeMonotoneWeightInUnitInterval) {
  for (double width : {0.5, 1.0, robust::kDefaultWidth}) {
    const auto kernel = registry_.create(GetParam(), width);
    const Rho zero = eval(*kernel, 0.0);
    EXPECT_EQ(zero.v[0], 0.0);
    EXPECT_DOUBLE_EQ(zero.v[1], 1.0);
    // Like s near zero: rho(s) = s (1 + O(sqrt(s / width^2))) (fair's correction is the
    // square root's, the others' O(s)).
    const double tiny = 1e-10 * kink(GetParam(), width);
    EXPECT_NEAR(eval(*kernel, tiny).v[0], tiny, 1e-4 * tiny);
    double previous = 0.0;
    for (double s = 0.0; s < 50 * kink(GetParam(), width); s += 0.01 * kink(GetParam(), width)) {
      const Rho r = eval(*kernel, s);
      EXPECT_GE(r.v[0], previous) << "s " << s;
      EXPECT_GE(r.v[1], 0.0) << "s " << s;
      EXPECT_LE(r.v[1], 1.0) << "s " << s;
      EXPECT_LE(r.v[0], s * (1 + 1e-12)) << "rho(s) <= s, s " << s;
      previous = r.v[0];
    }
  }
}

TEST_P(RobustKernels, ContinuousAtTheKink) {
  const double width = 1.7;
  const auto kernel = registry_.create(GetParam(), width);
  const double knee = kink(GetParam(), width);
  const Rho below = eval(*kernel, knee * (1 - 1e-10)), above = eval(*kernel, knee * (1 + 1e-10));
  EXPECT_NEAR(below.v[0], above.v[0], 1e-8 * knee);
  // Only saturated/tls (and Huber's rho'' aside) have a jump in the weight.
  if (GetParam() != "saturated" && GetParam() != "tls") {
    EXPECT_NEAR(below.v[1], above.v[1], 1e-8);
  }
}

INSTANTIATE_TEST_SUITE_P(Robust, RobustKernels, ::testing::ValuesIn(kKernelNames),
                         [](const auto& info) {
                           std::string n = info.param;
                           for (char& c : n)
                             if (c == '-') c = '_';
                           return n;
                         });

TEST(Robust_Kernels, KnownValues) {
  double rho[3];
  robust::HuberKernel(2.0).robustify(9.0, rho);  // |e| = 3 > 2: 2*2*3 - 4
  EXPECT_DOUBLE_EQ(rho[0], 8.0);
  EXPECT_DOUBLE_EQ(rho[1], 2.0 / 3.0);
  robust::CauchyKernel(1.0).robustify(std::exp(1.0) - 1.0, rho);
  EXPECT_DOUBLE_EQ(rho[0], 1.0);
  robust::TukeyKernel(1.0).robustify(4.0, rho);
  EXPECT_DOUBLE_EQ(rho[0], 1.0 / 3.0);
  EXPECT_EQ(rho[1], 0.0);
  robust::DcsKernel(1.0).robustify(3.0, rho);  // w = (2 / 4)^2, rho = (9 - 1) / 4
  EXPECT_DOUBLE_EQ(rho[1], 0.25);
  EXPECT_DOUBLE_EQ(rho[0], 2.0);
  robust::TruncatedLeastSquaresKernel(2.0).robustify(5.0, rho);
  EXPECT_EQ(rho[0], 4.0);
  EXPECT_EQ(rho[1], 0.0);
  robust::GemanMcClureKernel(1.0).robustify(1.0, rho);
  EXPECT_DOUBLE_EQ(rho[0], 0.5);
  EXPECT_DOUBLE_EQ(rho[1], 0.25);
}

TEST(Robust_Registry, RegistersTheTenKernelsWithDocumentedWidths) {
  const Registries r = kernelRegistry();
  std::vector<std::string> names;
  for (const auto* k : r.kernels.entries()) {
    names.push_back(k->name);
    EXPECT_EQ(k->origin, "robust");
    EXPECT_EQ(k->default_width, k->name == "dcs" ? 1.0 : robust::kDefaultWidth) << k->name;
  }
  EXPECT_EQ(names, kKernelNames);
  EXPECT_NEAR(robust::kDefaultWidth * robust::kDefaultWidth, 7.814727903251178, 1e-12);
  Registries again = kernelRegistry();
  EXPECT_THROW(robust::registerKernels(again.kernels), RegistryError);
}

TEST(Robust_Spec, ParsesNameAndWidth) {
  const Registries r = kernelRegistry();
  const auto a = robust::parseKernelSpec("cauchy:0.5", r.kernels);
  EXPECT_EQ(a.name, "cauchy");
  EXPECT_EQ(a.width, 0.5);
  const auto b = robust::parseKernelSpec("huber", r.kernels);
  EXPECT_TRUE(std::isnan(b.width));
  EXPECT_EQ(robust::createKernel(b, r.kernels)->width(), robust::kDefaultWidth);
  EXPECT_EQ(robust::createKernel(robust::parseKernelSpec("dcs:1e1", r.kernels), r.kernels)->width(),
            10.0);
}

TEST(Robust_Spec, MalformedSpecsNameTheProblemAndTheKernels) {
  const Registries r = kernelRegistry();
  const std::pair<const char*, const char*> cases[] = {
      {"huber:", "no width after ':'"},
      {"huber:abc", "width 'abc' is not a number"},
      {"huber:1x", "width '1x' is not a number"},
      {"huber:-1", "width '-1' is not positive and finite"},
      {"huber:0", "width '0' is not positive and finite"},
      {"huber:inf", "width 'inf' is not positive and finite"},
      {"huber:nan", "width 'nan' is not positive and finite"},
      {"nope", "unknown kernel 'nope'"},
      {"", "no kernel name"},
      {":2", "no kernel name"}};
  for (const auto& [spec, why] : cases) {
    try {
      (void)robust::parseKernelSpec(spec, r.kernels);
      ADD_FAILURE() << "accepted '" << spec << "'";
    } catch (const RegistryError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(why), std::string::npos) << msg;
      EXPECT_NE(msg.find("known: cauchy, dcs, fair, geman-mcclure, huber, pseudo-huber, "
                         "saturated, tls, tukey, welsch"),
                std::string::npos)
          << msg;
    }
  }
}

/// Poses 0..n-1 on the x axis 1 m apart (the truth), odometry between consecutive ones
/// (information 100 I), pose 0 fixed.
Graph line(int n) {
  Graph g;
  for (int i = 0; i < n; ++i) {
    auto v = std::make_unique<VertexSE2>();
    v->setId(i);
    v->setEstimate(SE2(i, 0, 0));
    v->setFixed(i == 0);
    g.addVertex(std::move(v));
  }
  for (int i = 0; i + 1 < n; ++i) {
    auto e = std::make_unique<EdgeSE2>();
    e->setVertexIds({i, i + 1});
    e->setMeasurement(SE2(1, 0, 0));
    e->setInformation(100 * Eigen::Matrix3d::Identity());
    g.addEdge(std::move(e));
  }
  return g;
}

void addSE2(Graph& g, int i, int j, const SE2& z) {
  auto e = std::make_unique<EdgeSE2>();
  e->setVertexIds({i, j});
  e->setMeasurement(z);
  e->setInformation(100 * Eigen::Matrix3d::Identity());
  g.addEdge(std::move(e));
}

TEST(Robust_Selection, LoopClosuresTagsAndAll) {
  const Registries r = kernelRegistry();
  Graph g = line(5);
  addSE2(g, 0, 3, SE2(3, 0, 0));   // loop closure
  addSE2(g, 4, 2, SE2(-2, 0, 0));  // loop closure, ids in either order
  auto landmark = std::make_unique<VertexXY>();
  landmark->setId(5);  // consecutive to pose 4, but not a pose
  g.addVertex(std::move(landmark));
  auto obs = std::make_unique<EdgeSE2XY>();
  obs->setVertexIds({4, 5});
  obs->setMeasurement(Eigen::Vector2d(1, 1));
  g.addEdge(std::move(obs));
  auto far_obs = std::make_unique<EdgeSE2XY>();
  far_obs->setVertexIds({0, 5});
  far_obs->setMeasurement(Eigen::Vector2d(5, 1));
  g.addEdge(std::move(far_obs));
  auto prior = std::make_unique<EdgePriorSE2>();
  prior->setVertexIds({0});
  g.addEdge(std::move(prior));

  std::vector<bool> loops;
  for (const auto& e : g.edges()) loops.push_back(robust::isLoopClosure(*e, g));
  EXPECT_EQ(loops,
            (std::vector<bool>{false, false, false, false, true, true, false, false, false}));

  EXPECT_EQ(robust::applyRobustKernel(g, r.types, r.kernels, "cauchy:2", "loop-closures"), 2u);
  for (std::size_t k = 0; k < g.edges().size(); ++k) {
    const RobustKernel* kernel = g.edges()[k]->robustKernel();
    EXPECT_EQ(kernel != nullptr, loops[k]) << "edge " << k;
    if (kernel) {
      EXPECT_EQ(kernel->width(), 2.0);
    }
  }
  EXPECT_EQ(robust::applyRobustKernel(g, r.types, r.kernels, "huber", "EDGE_SE2_XY"), 2u);
  EXPECT_EQ(robust::applyRobustKernel(g, r.types, r.kernels, "huber", "EDGE_PRIOR_SE2"), 1u);
  EXPECT_EQ(robust::applyRobustKernel(g, r.types, r.kernels, "tukey:3", "all"), g.edges().size());
  EXPECT_EQ(robust::applyRobustKernel(g, r.types, r.kernels, "tukey:3", "EDGE_PRIOR_XY"),
            0u);  // none in g
  for (const char* bad : {"EDGE_NOPE", "VERTEX_SE2", "", "loops"}) {
    try {
      (void)robust::applyRobustKernel(g, r.types, r.kernels, "huber", bad);
      ADD_FAILURE() << "accepted selection '" << bad << "'";
    } catch (const RegistryError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("edge selection '" + std::string(bad) + "'"), std::string::npos) << msg;
      for (const char* tag : {"(edge tags: ", " EDGE_SE2,", " EDGE_SE2_XY,", " EDGE_PRIOR_SE2,"})
        EXPECT_NE(msg.find(tag), std::string::npos) << msg;
    }
  }
}

/// The line of 6 poses with a right loop closure 0-5 and a wrong one 0-3 that says pose 3
/// is 5 m to the left.
Graph lineWithOutlier() {
  Graph g = line(6);
  addSE2(g, 0, 5, SE2(5, 0, 0));
  addSE2(g, 0, 3, SE2(3, 5, 0));
  return g;
}

Summary optimize(Graph& g, const std::string& solver) {
  SolverRegistry solvers;
  solvers::registerSolvers(solvers);
  Optimizer::Options options;
  options.linear_solver = solver;
  options.algorithm = Algorithm::kLevenbergMarquardt;
  Optimizer optimizer(g, solvers, options);
  return optimizer.optimize();
}

Eigen::Vector2d position(const Graph& g, VertexId id) {
  return static_cast<const VertexSE2*>(g.vertex(id))->estimate().translation();
}

TEST(Robust_Optimization, KernelOnTheWrongLoopClosureKeepsThePosesWhereTheyAre) {
  const Registries r = kernelRegistry();
  Graph plain = lineWithOutlier();
  const Summary s0 = optimize(plain, "eigen-ldlt");
  ASSERT_TRUE(s0.succeeded()) << s0.message;
  // Least squares spreads the 5 m over the graph: pose 3 moves 3.37 m to the left.
  EXPECT_NEAR(position(plain, 3).y(), 3.37106, 1e-4);
  EXPECT_NEAR(s0.final_chi2, 796.602, 1e-2);
  EXPECT_EQ(s0.robust_edges, 0u);
  EXPECT_DOUBLE_EQ(s0.final_cost, s0.final_chi2);

  // Largest distance of a pose from the truth with the kernel (default width) on both loop
  // closures: Huber bounds the outlier's pull, Cauchy nearly removes it, the redescending
  // kernels remove it.
  const struct {
    const char* spec;
    double max_off, tolerance;
  } cases[] = {{"huber", 0.64053, 1e-4},         {"cauchy", 0.036255, 1e-5}, {"dcs", 0, 1e-4},
               {"geman-mcclure", 1.12e-4, 1e-5}, {"tukey", 0, 1e-9},         {"tls", 0, 1e-9}};
  for (const auto& [spec, want_off, tolerance] : cases) {
    SCOPED_TRACE(spec);
    Graph g = lineWithOutlier();
    EXPECT_EQ(robust::applyRobustKernel(g, r.types, r.kernels, spec, "loop-closures"), 2u);
    const Summary s = optimize(g, "eigen-ldlt");
    ASSERT_TRUE(s.succeeded()) << s.message;
    EXPECT_EQ(s.robust_edges, 2u);
    double max_off = 0;
    for (int i = 0; i < 6; ++i)
      max_off = std::max(max_off, (position(g, i) - Eigen::Vector2d(i, 0)).norm());
    EXPECT_NEAR(max_off, want_off, tolerance);
    // The robust cost is the sum of rho over the edges; chi2 the raw sum.
    double cost = 0, chi2 = 0;
    for (const auto& e : g.edges()) {
      e->computeError();
      chi2 += e->chi2();
      cost += e->robustChi2();
    }
    EXPECT_NEAR(s.final_cost, cost, 1e-9 * cost);
    EXPECT_NEAR(s.final_chi2, chi2, 1e-9 * chi2);
    EXPECT_LT(s.final_cost, 0.5 * s.final_chi2);
  }
}

TEST(Robust_Optimization, JacobianFormSolverAgreesWithNormalEquations) {
  const Registries r = kernelRegistry();
  Graph h_form = lineWithOutlier(), j_form = lineWithOutlier();
  (void)robust::applyRobustKernel(h_form, r.types, r.kernels, "cauchy:1", "all");
  (void)robust::applyRobustKernel(j_form, r.types, r.kernels, "cauchy:1", "all");
  const Summary sh = optimize(h_form, "eigen-ldlt");
  const Summary sj = optimize(j_form, "eigen-qr");
  ASSERT_TRUE(sh.succeeded()) << sh.message;
  ASSERT_TRUE(sj.succeeded()) << sj.message;
  EXPECT_NEAR(sh.final_cost, sj.final_cost, 1e-9 * sh.final_cost);
  for (int i = 0; i < 6; ++i) {
    EXPECT_LT((position(h_form, i) - position(j_form, i)).norm(), 1e-8) << "pose " << i;
  }
}

}  // namespace
