// SPDX-License-Identifier: MIT
// Regression on the public benchmark graphs: the optimizer must reach the best known
// chi2 (to 1e-6 relative, or lower). Skipped when the dataset folder is absent.
#include <gtest/gtest.h>

#include <Eigen/SparseCholesky>
#include <random>
#include <sstream>

#include "../common/hessian_reference.h"
#include "../common/test_util.h"
#include "graphslam/init/chordal_se3.h"
#include "graphslam/init/global_se2.h"
#include "graphslam/io/g2o.h"
#include "graphslam/optimizer/marginals.h"
#include "graphslam/optimizer/optimizer.h"
#include "graphslam/solvers/register.h"
#include "graphslam/support/logging.h"
#include "graphslam/types_slam2d/register.h"
#include "graphslam/types_slam3d/register.h"

using namespace graphslam;

namespace {

/// The slam2d types, the solvers and a public dataset loaded through them.
struct Dataset {
  TypeRegistry types;
  SolverRegistry solvers;
  std::string path;
  io::LoadResult loaded;

  explicit Dataset(const std::string& file) : path(test::dataDir() + "/" + file) {
    types_slam2d::registerTypes(types);
    types_slam3d::registerTypes(types);
    solvers::registerSolvers(solvers);
    if (present()) loaded = io::loadG2o(path, types);
  }
  [[nodiscard]] bool present() const { return test::fileExists(path); }
  [[nodiscard]] std::string missing() const {
    return "dataset " + path + " not found (set GRAPHSLAM_DATA to the datasets folder)";
  }
};

struct DatasetCase {
  std::string file;
  double target_chi2;  ///< best known; we must reach it within 1e-6 relative or go lower
  double our_chi2;     ///< what graphslam reaches (regression: within 1e-6 relative)
  bool global_init;    ///< the tool's default; without it, start from the file's estimates
  Optimizer::Options options;
};

Optimizer::Options defaults() { return Optimizer::Options{}; }

Optimizer::Options gaussNewton() {
  Optimizer::Options o;
  o.algorithm = Algorithm::kGaussNewton;
  return o;
}

std::ostream& operator<<(std::ostream& os, const DatasetCase& c) { return os << c.file; }

class Datasets_Regression : public ::testing::TestWithParam<DatasetCase> {};

TEST_P(Datasets_Regression, ReachesBestKnownChi2) {
  const DatasetCase& c = GetParam();
  Dataset data(c.file);
  if (!data.present()) GTEST_SKIP() << data.missing();
  ASSERT_TRUE(data.loaded.ok()) << data.loaded.diagnostics.at(0).str();
  auto& loaded = data.loaded;
  const SolverRegistry& solvers = data.solvers;
  support::setLogLevel(support::LogLevel::kError);
  if (c.global_init) {
    const auto report = init::initializeGlobal(loaded.graph);
    const auto report3d = init::initializeChordal3d(loaded.graph);
    ASSERT_GT(report.poses + report3d.poses, 0u) << report.message << report3d.message;
  }
  Optimizer optimizer(loaded.graph, solvers, c.options);
  const Summary s = optimizer.optimize();
  std::printf("%s: chi2 %.10g -> %.10g in %d iterations, %.3f s (%s)\n", c.file.c_str(),
              s.initial_chi2, s.final_chi2, s.iterations, s.total_time, toString(s.status));
  EXPECT_TRUE(s.succeeded()) << s.message;
  EXPECT_LE(s.final_chi2, c.target_chi2 * (1 + 1e-6));
  EXPECT_NEAR(s.final_chi2, c.our_chi2, 1e-6 * c.our_chi2);
}

std::vector<DatasetCase> cases() {
  // Best known values: g2o's best configuration per file (landmark graphs: g2o's best
  // result); m3500b: a lower stationary point found with GTSAM. Where graphslam's default
  // (global initialisation + Gauss-Newton with LM fallback) lands in a lower minimum the
  // second column says so.
  return {
      {"intel.g2o", 45.004696, 45.00469581, true, defaults()},
      {"m3500.g2o", 137.912951, 137.9129509, true, defaults()},
      {"city10000.g2o", 511.985164, 511.9851636, true, defaults()},
      {"ais2klinik.g2o", 172.81558, 172.8155793, true, defaults()},
      {"csail.g2o", 38.956286, 38.95628587, true, defaults()},
      {"fr079.g2o", 37.599116, 37.59911592, true, defaults()},
      {"mit.g2o", 526.331038, 41.16326884, true, defaults()},
      {"m3500b.g2o", 4212.0166, 2054.715918, true, defaults()},
      {"dlr.g2o", 56860.35, 56860.35268, true, defaults()},
      {"victoria_park.g2o", 503457.85, 6184.1206, true, defaults()},
      {"citytrees10000.g2o", 8668.93, 8668.928087, true, defaults()},
      // From the files' own estimates, plain Gauss-Newton (as g2o's best configuration).
      {"intel.g2o", 45.004696, 45.00469581, false, gaussNewton()},
      {"city10000.g2o", 511.985164, 511.9851636, false, gaussNewton()},
      {"ais2klinik.g2o", 172.81558, 172.8155793, false, gaussNewton()},
      // 3D, from the chordal initialisation. torus3d and sphere_bignoise_vertex3 land in
      // lower minima than g2o's best (19972.23; LM 785282.87). garage: g2o's 1.238684 is
      // 5e-6 lower than this stationary point of the exact objective (gradient below 1e-7
      // checked independently); g2o reads VERTEX_SE3:QUAT quaternions without normalising
      // them, so its rotations carry the file's rounding (see docs/BENCHMARKS.md).
      {"sphere2500.g2o", 727.149471, 727.1496672, true, defaults()},
      {"garage.g2o", 1.2386906, 1.23869058, true, defaults()},
      {"smallgrid3d.g2o", 458.153787, 458.1537843, true, defaults()},
      {"tinygrid3d.g2o", 6.727882, 6.727881617, true, defaults()},
      {"torus3d.g2o", 19972.23, 14574.74644, true, defaults()},
      {"sphere_bignoise_vertex3.g2o", 785282.87, 743862.7209, true, defaults()},
  };
}

INSTANTIATE_TEST_SUITE_P(Public, Datasets_Regression, ::testing::ValuesIn(cases()),
                         [](const auto& info) {
                           std::string s = info.param.file.substr(0, info.param.file.find('.'));
                           return s + (info.param.global_init ? "_default" : "_gn_from_file");
                         });

/// One iteration of the optimizer with `options` on `data` from the global initial guess
/// (the tool's default start), into `summary`.
void firstIteration(Dataset& data, Optimizer::Options options, Summary& summary) {
  ASSERT_TRUE(data.loaded.ok()) << data.loaded.diagnostics.at(0).str();
  support::setLogLevel(support::LogLevel::kError);
  const auto report = init::initializeGlobal(data.loaded.graph);
  ASSERT_TRUE(report.message.empty()) << report.message;
  options.max_iterations = 1;
  Optimizer optimizer(data.loaded.graph, data.solvers, options);
  summary = optimizer.optimize();
  ASSERT_EQ(summary.per_iteration.size(), 1u);
}

// m3500b from the global initialisation: the first undamped step raises chi2 (7743 ->
// 36583); the default optimizer then takes a dogleg step from the same factorisation
// (Options::first_step_dogleg), and that step alone reaches the best known chi2.
/// A 3D graph written with all digits reads back with the same chi2.
TEST(Datasets_RoundTrip, ThreeDimensionalFilesReadBackWithTheSameChi2) {
  for (const char* file : {"sphere2500.g2o", "garage.g2o"}) {
    Dataset data(file);
    if (!data.present()) GTEST_SKIP() << data.missing();
    ASSERT_TRUE(data.loaded.ok()) << data.loaded.diagnostics.at(0).str();
    init::initializeChordal3d(data.loaded.graph);
    const double chi2 = data.loaded.graph.chi2();
    std::stringstream text;
    io::writeG2o(text, data.loaded.graph, data.types);
    auto back = io::readG2o(text, "again", data.types);
    ASSERT_TRUE(back.ok()) << back.diagnostics.at(0).str();
    EXPECT_NEAR(back.graph.chi2(), chi2, 1e-12 * chi2) << file;
  }
}

TEST(Datasets_FirstStep, M3500bRisingFirstStepBecomesDogleg) {
  for (const bool dogleg : {true, false}) {
    Dataset data("m3500b.g2o");
    if (!data.present()) GTEST_SKIP() << data.missing();
    Optimizer::Options options;
    options.first_step_dogleg = dogleg;
    Summary s;
    firstIteration(data, options, s);
    if (HasFatalFailure()) return;
    const IterationStats& first = s.per_iteration[0];
    std::printf(
        "m3500b, first_step_dogleg %d: chi2 %.6g -> %.6g, %d factorisation(s), %d halvings\n",
        dogleg, s.initial_chi2, first.chi2, first.factorizations,
        static_cast<int>(first.strategy.value("halvings")));
    EXPECT_NEAR(s.initial_chi2, 7743.03, 0.01);
    EXPECT_EQ(first.factorizations, 1);
    if (dogleg) {
      // The graph holds the step taken (the undamped one is undone at the end: above
      // the best chi2 seen).
      EXPECT_NEAR(data.loaded.graph.chi2(), first.chi2, 1e-9 * first.chi2);
      EXPECT_EQ(first.strategy.value("halvings"), 2);
      // The Gauss-Newton step raised chi2 by 5.1 times the decrease its model promised:
      // the first trial is already at a quarter of it (firstStepDogleg).
      EXPECT_EQ(first.strategy.value("trials"), 1);
      EXPECT_LE(first.chi2, 4212.0166);
    } else {
      EXPECT_EQ(first.strategy.value("halvings"), 0);
      EXPECT_EQ(first.strategy.value("trials"), 0);
      EXPECT_GT(first.chi2, 30000.0);  // the undamped step: 36583
    }
  }
}

// mit from the global initialisation: the first undamped step raises chi2 only just
// (71.545 -> 71.570, its model promised a decrease of 30.3), so the dogleg's first trial
// is at half the Gauss-Newton step, where the model agrees (50.43).
TEST(Datasets_FirstStep, MitSlightlyRisingFirstStepTriesHalfFirst) {
  Dataset data("mit.g2o");
  if (!data.present()) GTEST_SKIP() << data.missing();
  Summary s;
  firstIteration(data, Optimizer::Options{}, s);
  if (HasFatalFailure()) return;
  const IterationStats& first = s.per_iteration[0];
  EXPECT_NEAR(s.initial_chi2, 71.5448, 1e-3);
  EXPECT_EQ(first.strategy.value("halvings"), 1);
  EXPECT_EQ(first.strategy.value("trials"), 1);
  EXPECT_NEAR(first.chi2, 50.4336, 1e-3);
}

// From victoria_park's own estimates the default optimizer's undamped phase ends far from
// the optimum and Levenberg-Marquardt takes over in a long, flat valley: hundreds of good
// steps in a row. Each shrinks lambda; without a floor it fell to 1e-23 of the diagonal,
// where 11 doublings cannot bring the damping back, and the optimizer stopped with "no
// decreasing step" at chi2 772207.8 (the steps were not at a minimum). With the floor it
// goes on to converge.
TEST(Datasets_FromFile, VictoriaParkDampingDoesNotUnderflow) {
  Dataset data("victoria_park.g2o");
  if (!data.present()) GTEST_SKIP() << data.missing();
  ASSERT_TRUE(data.loaded.ok()) << data.loaded.diagnostics.at(0).str();
  support::setLogLevel(support::LogLevel::kError);
  Optimizer::Options options;
  options.max_iterations = 300;
  Optimizer optimizer(data.loaded.graph, data.solvers, options);
  const Summary s = optimizer.optimize();
  std::printf("victoria_park from the file: chi2 %.10g -> %.10g in %d iterations (%s: %s)\n",
              s.initial_chi2, s.final_chi2, s.iterations, toString(s.status), s.message.c_str());
  EXPECT_EQ(s.status, TerminationStatus::kConverged) << s.message;
  EXPECT_LT(s.final_chi2, 772207.0);
  double smallest_lambda = 1e300;
  for (const auto& it : s.per_iteration) {
    if (it.strategy.value("lambda") > 0)
      smallest_lambda = std::min(smallest_lambda, it.strategy.value("lambda"));
  }
  EXPECT_GT(smallest_lambda, 1e-20);
}

/// Marginals of every vertex of an optimised large graph, checked on random vertices
/// against columns of H^-1 from an independent sparse solve (Eigen's LDL^T with its own
/// scalar AMD ordering on an independently assembled H).
class Datasets_Marginals : public ::testing::TestWithParam<std::string> {};

TEST_P(Datasets_Marginals, AllBlocksMatchIndependentSolves) {
  Dataset data(GetParam());
  if (!data.present()) GTEST_SKIP() << data.missing();
  ASSERT_TRUE(data.loaded.ok()) << data.loaded.diagnostics.at(0).str();
  auto& loaded = data.loaded;
  const SolverRegistry& solvers = data.solvers;
  Graph& g = loaded.graph;
  support::setLogLevel(support::LogLevel::kError);
  ASSERT_TRUE(init::initializeGlobal(g).message.empty());
  Optimizer optimizer(g, solvers);
  ASSERT_TRUE(optimizer.optimize().succeeded());

  MarginalCovariance::Options marginal_options;
  marginal_options.solvers = &solvers;
  MarginalCovariance marginals(marginal_options);
  const MarginalSummary s = marginals.computeAll(g);
  ASSERT_TRUE(s.ok()) << s.report();
  ASSERT_EQ(s.gauge_fixed.size(), 1u);
  std::printf("%s: marginals of %zu vertices, %d unknowns, nnz(L) %zu, %.3f s\n",
              GetParam().c_str(), marginals.blocks().size(), s.system_dimension, s.factor_nonzeros,
              s.total_time);

  const VertexId gauge = s.gauge_fixed[0];
  g.vertex(gauge)->setFixed(true);  // the same system as the marginals solved
  const test::HessianReference ref(g);
  g.vertex(gauge)->setFixed(false);
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(ref.h);
  ASSERT_EQ(ldlt.info(), Eigen::Success);
  std::vector<VertexId> ids;
  for (const auto& [id, c] : ref.column) ids.push_back(id);
  std::mt19937 rng(8);
  std::uniform_int_distribution<std::size_t> pick(0, ids.size() - 1);
  Eigen::VectorXd e = Eigen::VectorXd::Zero(ref.h.rows());
  // These graphs are ill-conditioned (victoria_park: H_ii from 5 to 2e5, variances up to
  // 14 m^2): two exact factorisations agree to about 1e-8 relative, not to 1e-9.
  double worst = 0.0;
  for (int trial = 0; trial < 40; ++trial) {
    const VertexId id = ids[pick(rng)];
    const int c0 = ref.column.at(id);
    const Eigen::MatrixXd& block = marginals.block(id);
    for (int c = 0; c < block.cols(); ++c) {
      e[c0 + c] = 1.0;
      const Eigen::VectorXd col = ldlt.solve(e);
      e[c0 + c] = 0.0;
      const Eigen::VectorXd want = col.segment(c0, block.rows());
      const double rel = (block.col(c) - want).cwiseAbs().maxCoeff() / want.cwiseAbs().maxCoeff();
      worst = std::max(worst, rel);
      EXPECT_LE(rel, 1e-6) << "vertex " << id << " column " << c;
    }
  }
  std::printf("largest relative difference to the independent solves: %.2e\n", worst);
  EXPECT_EQ(marginals.block(gauge), Eigen::MatrixXd::Zero(3, 3));
}

INSTANTIATE_TEST_SUITE_P(Public, Datasets_Marginals,
                         ::testing::Values("victoria_park.g2o", "city10000.g2o"),
                         [](const auto& info) {
                           return info.param.substr(0, info.param.find('.'));
                         });

}  // namespace
