// SPDX-License-Identifier: MIT
// Values that break arithmetic say what is wrong: an initial chi2 that is not finite names
// its edge and tells an overflow from a non-finite error; an edge whose information matrix
// spans more than double arithmetic resolves is named as the reason a vertex is undetermined.
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "graphslam/diagnostics/observability.h"
#include "graphslam/io/g2o.h"
#include "graphslam/optimizer/optimizer.h"
#include "graphslam/solvers/register.h"
#include "graphslam/types_slam2d/register.h"

using namespace graphslam;

namespace {

/// Two poses, the first fixed, joined by one EDGE_SE2 with `measurement_x` and the
/// information diag(i, i, 1) written as text.
io::LoadResult twoPoses(const TypeRegistry& types, const std::string& measurement_x,
                        const std::string& info) {
  std::istringstream in("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 0 0 0\nFIX 0\nEDGE_SE2 0 1 " +
                        measurement_x + " 0 0 " + info + " 0 0 " + info + " 0 1\n");
  return io::readG2o(in, "t.g2o", types);
}

}  // namespace

TEST(Optimizer_BadValues, NonFiniteInitialChi2NamesTheEdgeAndTheOverflow) {
  TypeRegistry types;
  types_slam2d::registerTypes(types);
  SolverRegistry solvers;
  solvers::registerSolvers(solvers);
  // Optimises the two poses from their file estimates (no initialisation).
  const auto optimize = [&](const std::string& measurement_x, const std::string& info) {
    auto r = twoPoses(types, measurement_x, info);
    EXPECT_TRUE(r.ok());
    Optimizer opt(r.graph, solvers);
    return opt.optimize();
  };
  const Summary huge_error = optimize("1e300", "1e300");  // error 1e300: chi2 overflows
  EXPECT_EQ(huge_error.status, TerminationStatus::kNumericalFailure);
  EXPECT_EQ(huge_error.failed_edge, 0);
  EXPECT_NE(huge_error.message.find("initial chi2 is not finite: the edge joining vertices 0, 1: "
                                    "its error is finite (largest entry 1e+300) but e^T Omega e "
                                    "overflows"),
            std::string::npos)
      << huge_error.message;
  const Summary huge_information = optimize("10", "1e308");
  EXPECT_EQ(huge_information.failed_edge, 0);
  EXPECT_NE(huge_information.message.find(
                "overflows the range of a double (information entries up to 1e+308)"),
            std::string::npos)
      << huge_information.message;
  const Summary fine = optimize("10", "1");
  EXPECT_TRUE(fine.succeeded()) << fine.message;
  EXPECT_EQ(fine.failed_edge, -1);
}

TEST(Optimizer_BadValues, IllConditionedInformationIsNamedAsTheReason) {
  TypeRegistry types;
  types_slam2d::registerTypes(types);
  auto r = twoPoses(types, "1", "1e308");  // diag(1e308, 1e308, 1): positive definite
  ASSERT_TRUE(r.ok());
  const ObservabilityReport report = checkObservability(r.graph);
  ASSERT_EQ(report.undetermined.size(), 1u);
  EXPECT_NE(report.undetermined[0].reason.find(
                "the information matrix of one of its edges has eigenvalues 1e+308 times apart"),
            std::string::npos)
      << report.undetermined[0].reason;
  auto fine = twoPoses(types, "1", "1e6");
  ASSERT_TRUE(fine.ok());
  EXPECT_TRUE(checkObservability(fine.graph).ok());
}
