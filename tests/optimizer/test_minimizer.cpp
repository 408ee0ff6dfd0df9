// SPDX-License-Identifier: MIT
// The minimizer's step strategies, each on its own: Gauss-Newton, Levenberg-Marquardt (both
// dampings), dogleg and the default; recovery from systems that do not factorise.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "graphslam/core/fixed_edge.h"
#include "graphslam/optimizer/optimizer.h"
#include "graphslam/simulation/simulator.h"
#include "graphslam/solvers/register.h"
#include "graphslam/support/error.h"
#include "graphslam/types_slam2d/vertex_xy.h"

using namespace graphslam;
using types_slam2d::VertexXY;

namespace {

SolverRegistry allSolvers() {
  SolverRegistry s;
  solvers::registerSolvers(s);
  return s;
}

/// Distance between two points: e = |b - a| - z (numeric Jacobians).
class EdgeRange final : public BaseBinaryEdge<1, double, VertexXY, VertexXY> {
 public:
  ErrorVector evaluate(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const override {
    return ErrorVector((b - a).norm() - measurement());
  }
};

/// Displacement between two points: e = (b - a) - z.
class EdgeOffset final : public BaseBinaryEdge<2, Eigen::Vector2d, VertexXY, VertexXY> {
 public:
  ErrorVector evaluate(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const override {
    return (b - a) - measurement();
  }
};

void addPoint(Graph& g, VertexId id, const Eigen::Vector2d& p, bool fixed = false) {
  auto v = std::make_unique<VertexXY>();
  v->setId(id);
  v->setEstimate(p);
  v->setFixed(fixed);
  g.addVertex(std::move(v));
}

/// Point 0 fixed, point 1 placed by an offset from it, point 2 seen only by a range from
/// point 1: H is singular in point 2's tangential direction.
Graph rangeOnlyPoint() {
  Graph g;
  addPoint(g, 0, {0, 0}, true);
  addPoint(g, 1, {0.5, 0.2});
  addPoint(g, 2, {3, 1});
  auto offset = std::make_unique<EdgeOffset>();
  offset->setVertexIds({0, 1});
  offset->setMeasurement({1, 0});
  g.addEdge(std::move(offset));
  auto range = std::make_unique<EdgeRange>();
  range->setVertexIds({1, 2});
  range->setMeasurement(2.0);
  g.addEdge(std::move(range));
  return g;
}

Summary optimize(Graph& g, Algorithm algorithm, const std::string& solver,
                 Optimizer::Options options = {}) {
  const SolverRegistry solvers = allSolvers();
  options.algorithm = algorithm;
  options.linear_solver = solver;
  Optimizer optimizer(g, solvers, options);
  return optimizer.optimize();
}

/// A pose graph with landmarks from its odometry; larger angle noise makes the first
/// Gauss-Newton steps overshoot.
simulation::SimulatedGraph manhattan(double sigma_theta = 0.01) {
  simulation::ManhattanOptions o;
  o.sigma_theta = sigma_theta;
  o.num_poses = 300;
  o.num_landmarks = 40;
  o.seed = 7;
  return simulation::simulateManhattan(o);
}

}  // namespace

TEST(Minimizer_Strategies, EveryAlgorithmReachesTheSameOptimum) {
  auto reference = manhattan();
  const Summary ref = optimize(reference.graph, Algorithm::kGaussNewtonFallback, "auto");
  ASSERT_EQ(ref.status, TerminationStatus::kConverged) << ref.message;
  ASSERT_LT(ref.final_chi2, 0.05 * ref.initial_chi2);
  struct Case {
    Algorithm algorithm;
    Optimizer::Options::Damping damping;
  };
  for (const Case c : {Case{Algorithm::kGaussNewton, {}}, Case{Algorithm::kLevenbergMarquardt, {}},
                       Case{Algorithm::kLevenbergMarquardt, Optimizer::Options::Damping::kDiagonal},
                       Case{Algorithm::kDogleg, {}}}) {
    auto sim = manhattan();
    Optimizer::Options options;
    options.damping = c.damping;
    options.max_iterations = 200;
    const Summary s = optimize(sim.graph, c.algorithm, "eigen-ldlt", options);
    SCOPED_TRACE(std::string(toString(c.algorithm)) + " damping " +
                 std::to_string(static_cast<int>(c.damping)));
    EXPECT_EQ(s.status, TerminationStatus::kConverged) << s.message;
    EXPECT_NEAR(s.final_chi2, ref.final_chi2, 1e-6 * ref.final_chi2);
    for (const IterationStats& it : s.per_iteration) {
      EXPECT_EQ(it.strategy.value("lambda") > 0, c.algorithm == Algorithm::kLevenbergMarquardt)
          << it.iteration;
      EXPECT_EQ(it.strategy.value("trust_radius") > 0, c.algorithm == Algorithm::kDogleg)
          << it.iteration;
    }
  }
}

TEST(Minimizer_Strategies, LevenbergMarquardtStepsNeverRaiseTheObjective) {
  auto sim = manhattan();
  const Summary s = optimize(sim.graph, Algorithm::kLevenbergMarquardt, "eigen-ldlt");
  double previous = s.initial_cost;
  for (const IterationStats& it : s.per_iteration) {
    EXPECT_LE(it.chi2, previous) << it.iteration;
    previous = it.chi2;
  }
}

TEST(Minimizer_Dogleg, RadiusGrowsAfterGoodStepsAndStepsStayInside) {
  auto sim = manhattan();
  Optimizer::Options options;
  options.dogleg.initial_radius = 1e-3;  // far inside the Gauss-Newton step
  options.max_iterations = 200;
  const Summary s = optimize(sim.graph, Algorithm::kDogleg, "eigen-ldlt", options);
  EXPECT_EQ(s.status, TerminationStatus::kConverged) << s.message;
  ASSERT_GE(s.per_iteration.size(), 3u);
  EXPECT_DOUBLE_EQ(s.per_iteration[0].strategy.value("trust_radius"), 1e-3);
  // The model of a small step is good: the radius triples until the step is Gauss-Newton's.
  EXPECT_GT(s.per_iteration[1].strategy.value("trust_radius"), 2.9e-3);
  double previous = s.initial_cost;
  for (const IterationStats& it : s.per_iteration) {
    EXPECT_LE(it.chi2, previous) << it.iteration;  // only decreasing steps are accepted
    previous = it.chi2;
  }
}

TEST(Minimizer_Dogleg, RejectedStepsAreRetriedOnTheSameFactorisation) {
  // Starts far off (large angle noise) where undamped steps overshoot; which iterations do
  // depends on rounding, so several worlds are tried.
  int retried = 0;
  for (double sigma : {0.2, 0.3, 0.4, 0.5}) {
    auto sim = manhattan(sigma);
    Optimizer::Options options;
    options.dogleg.initial_radius = 1e6;  // the first steps are undamped Gauss-Newton steps
    options.max_iterations = 200;
    const Summary s = optimize(sim.graph, Algorithm::kDogleg, "eigen-ldlt", options);
    EXPECT_EQ(s.status, TerminationStatus::kConverged) << sigma << ": " << s.message;
    auto reference = manhattan(sigma);
    const Summary ref = optimize(reference.graph, Algorithm::kLevenbergMarquardt, "auto", options);
    EXPECT_NEAR(s.final_chi2, ref.final_chi2, 1e-6 * ref.final_chi2) << sigma;
    for (const IterationStats& it : s.per_iteration) {
      EXPECT_EQ(it.factorizations, 1) << it.iteration;  // one factorisation per iteration
      retried += it.strategy.value("trials") > 1 ? 1 : 0;
    }
  }
  EXPECT_GT(retried, 0);
}

TEST(Minimizer_Recovery, SingularSystemConvergesWithDampingAndFailsWithoutIt) {
  for (const char* solver : {"cholmod", "eigen-llt", "block-llt"}) {
    SCOPED_TRACE(solver);
    for (Algorithm a :
         {Algorithm::kGaussNewtonFallback, Algorithm::kLevenbergMarquardt, Algorithm::kDogleg}) {
      Graph g = rangeOnlyPoint();
      const Summary s = optimize(g, a, solver);
      EXPECT_EQ(s.status, TerminationStatus::kConverged) << toString(a) << ": " << s.message;
      EXPECT_LT(s.final_chi2, 1e-12) << toString(a);
    }
    Graph g = rangeOnlyPoint();
    const Summary gn = optimize(g, Algorithm::kGaussNewton, solver);
    EXPECT_EQ(gn.status, TerminationStatus::kNumericalFailure);
    if (std::string(solver) == "eigen-llt") continue;  // reports no column
    EXPECT_NE(gn.message.find("(at vertex 2)"), std::string::npos)
        << gn.message << " / " << toString(gn.status);
    EXPECT_NE(gn.message.find("single edge"), std::string::npos) << gn.message;
  }
}

TEST(Minimizer_Recovery, DefaultSwitchesToDampingWhenTheUndampedSystemFails) {
  Graph g = rangeOnlyPoint();
  const Summary s = optimize(g, Algorithm::kGaussNewtonFallback, "cholmod");
  EXPECT_EQ(s.status, TerminationStatus::kConverged) << s.message;
  // Undamped iterations until the factorisation fails, then damped ones only.
  std::size_t first_damped = 0;
  while (first_damped < s.per_iteration.size() &&
         s.per_iteration[first_damped].strategy.value("lambda") == 0.0) {
    ++first_damped;
  }
  ASSERT_GT(first_damped, 0u);
  ASSERT_LT(first_damped, s.per_iteration.size());
  for (std::size_t k = first_damped; k < s.per_iteration.size(); ++k) {
    EXPECT_GT(s.per_iteration[k].strategy.value("lambda"), 0.0) << k;
  }
}

TEST(Minimizer_ActiveEdges, InactiveEdgesAreLeftOutOfTheOptimisation) {
  Graph g = rangeOnlyPoint();
  // A wrong prior-like offset from point 0 to point 2 that, active, would pull point 2.
  auto wrong = std::make_unique<EdgeOffset>();
  wrong->setVertexIds({0, 2});
  wrong->setMeasurement({10, 10});
  Edge& e = g.addEdge(std::move(wrong));
  const auto version = g.structureVersion();
  g.setEdgeActive(e, false);
  EXPECT_FALSE(e.active());
  EXPECT_NE(g.structureVersion(), version);
  const Summary s = optimize(g, Algorithm::kLevenbergMarquardt, "cholmod");
  EXPECT_EQ(s.status, TerminationStatus::kConverged) << s.message;
  EXPECT_LT(s.final_chi2, 1e-12);  // the inactive edge's error is not in the objective
  EXPECT_LT(g.chi2(), 1e-12);      // Graph::chi2 sums the active edges...
  EXPECT_GT(e.chi2(), 1.0);        // ...after computing every error
  // Only inactive edges: point 3 is not optimised (nothing determines it).
  addPoint(g, 3, {7, 7});
  auto lone = std::make_unique<EdgeOffset>();
  lone->setVertexIds({0, 3});
  lone->setMeasurement({1, 1});
  g.setEdgeActive(g.addEdge(std::move(lone)), false);
  const Summary t = optimize(g, Algorithm::kGaussNewtonFallback, "cholmod");
  EXPECT_EQ(t.status, TerminationStatus::kConverged) << t.message;
  EXPECT_EQ(t.num_vertices, 2u);  // points 1 and 2
  EXPECT_EQ(static_cast<const VertexXY*>(g.vertex(3))->estimate(), Eigen::Vector2d(7, 7));
  g.setEdgeActive(e, true);
  const Summary u = optimize(g, Algorithm::kGaussNewtonFallback, "cholmod");
  EXPECT_GT(u.final_chi2, 1.0);  // active again, the wrong edge counts
  Graph other = rangeOnlyPoint();
  EXPECT_THROW(other.setEdgeActive(e, false), Error);
}

/// Undamped steps of `s` (before any damped one) that did not lower chi2 below the best.
int undampedRises(const Summary& s) {
  int rises = 0;
  double best = s.initial_cost;
  for (const IterationStats& it : s.per_iteration) {
    if (it.strategy.value("lambda") > 0) break;
    rises += it.chi2 >= best ? 1 : 0;
    best = std::min(best, it.chi2);
  }
  return rises;
}

TEST(Minimizer_NonMonotone, PatienceBoundsTheUndampedStepsThatDoNotImprove) {
  // A start far off enough for Gauss-Newton to overshoot (which world does depends on
  // rounding: the first of several that does).
  Optimizer::Options patient;
  patient.first_step_dogleg = false;
  patient.max_iterations = 200;
  double sigma = 0.0;
  Summary s;
  for (double candidate : {0.3, 0.4, 0.5, 0.6, 0.8}) {
    auto a = manhattan(candidate);
    s = optimize(a.graph, Algorithm::kGaussNewtonFallback, "eigen-ldlt", patient);
    if (undampedRises(s) > 0) {
      sigma = candidate;
      break;
    }
  }
  ASSERT_GT(sigma, 0.0) << "no world where Gauss-Newton overshoots";
  ASSERT_EQ(s.status, TerminationStatus::kConverged) << s.message;
  // With a patience of one, the first step that does not improve ends the undamped phase:
  // back to the best estimate, then damped steps only.
  Optimizer::Options impatient = patient;
  impatient.fallback_patience = 1;
  auto b = manhattan(sigma);
  const Summary t = optimize(b.graph, Algorithm::kGaussNewtonFallback, "eigen-ldlt", impatient);
  EXPECT_EQ(t.status, TerminationStatus::kConverged) << t.message;
  std::size_t k = 0;
  double best_t = t.initial_cost;
  while (k < t.per_iteration.size() && t.per_iteration[k].chi2 < best_t) {
    best_t = t.per_iteration[k].chi2;
    ++k;
  }
  ASSERT_LT(k, t.per_iteration.size());
  EXPECT_EQ(t.per_iteration[k].chi2, best_t);  // the restart returned to the best estimate
  for (std::size_t j = k + 1; j < t.per_iteration.size(); ++j) {
    EXPECT_GT(t.per_iteration[j].strategy.value("lambda"), 0.0) << j;
  }
}
