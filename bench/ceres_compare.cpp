// SPDX-License-Identifier: MIT
// graphslam and Ceres side by side on one .g2o file (EDGE_SE2 / EDGE_SE2_XY graphs, and
// EDGE_SE3:QUAT pose graphs): both
// start from the same estimates (the file's, after the tool's default global
// initialisation), both keep the same vertex fixed (the file's FIX, else graphslam's gauge
// rule: the lowest id), and both final states are scored by graphslam's Graph::chi2().
#include <ceres/ceres.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <cstdio>
#include <exception>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bench_common.h"
#include "graphslam/optimizer/linear_system.h"
#include "graphslam/optimizer/optimizer.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/edge_se2_xy.h"
#include "graphslam/types_slam3d/edges.h"

using namespace graphslam;
using types_slam2d::EdgeSE2;
using types_slam2d::EdgeSE2XY;
using types_slam3d::EdgeSE3;

namespace {

constexpr const char* kUsage =
    "usage: graphslam_ceres_compare FILE.g2o [--repeats N] [--threads N] [--max-iterations N]\n"
    "                               [--check-rel TOL] [--target CHI2]\n"
    "Optimises FILE (EDGE_SE2, EDGE_SE2_XY or EDGE_SE3:QUAT edges only) with graphslam's default\n"
    "options and\n"
    "with Ceres (Levenberg-Marquardt, SPARSE_NORMAL_CHOLESKY on SuiteSparse, autodiff costs with\n"
    "graphslam's error definitions whitened by the upper Cholesky factor of the information),\n"
    "both from the same globally initialised estimates, --repeats times (default 1; times are\n"
    "medians). Ceres' result is written back into the graph and scored with Graph::chi2().\n"
    "--threads sets Ceres' num_threads and graphslam's threads (default 1). With --check-rel, "
    "exits 1 when the two\n"
    "final chi2 differ by more than TOL relative. Prints key=value lines. Exit 77 when FILE\n"
    "does not exist, 2 for a file with other edge types. With --target, also prints each one's\n"
    "time to its first iterate with chi2 <= CHI2 (Ceres: cumulative time of that iteration).";

/// Wraps to [-pi, pi) as types_slam2d::normalizeAngle, for doubles and Jets.
template <typename T>
T wrapAngle(const T& a) {
  const T two_pi(2.0 * M_PI);
  return a - two_pi * ceres::floor((a + T(M_PI)) / two_pi);
}

/// EDGE_SE2 (types_slam2d/edge_se2.h): e = [R_z^T (R_i^T (t_j - t_i) - t_z);
/// wrap(theta_j - theta_i - theta_z)], residual U e with U^T U = Omega.
struct Se2Cost {
  Se2Cost(const types_slam2d::SE2& z, const Eigen::Matrix3d& sqrt_info)
      : z_t(z.translation()), z_theta(z.angle()), u(sqrt_info) {}

  template <typename T>
  bool operator()(const T* xi, const T* xj, T* residual) const {
    using std::cos;
    using std::sin;
    const T ci = cos(xi[2]), si = sin(xi[2]);
    const T dx = xj[0] - xi[0], dy = xj[1] - xi[1];
    const T d0 = ci * dx + si * dy - T(z_t.x());  // R_i^T (t_j - t_i) - t_z
    const T d1 = -si * dx + ci * dy - T(z_t.y());
    const double cz = std::cos(z_theta), sz = std::sin(z_theta);
    Eigen::Matrix<T, 3, 1> e;
    e[0] = cz * d0 + sz * d1;
    e[1] = -sz * d0 + cz * d1;
    e[2] = wrapAngle(xj[2] - xi[2] - T(z_theta));
    Eigen::Map<Eigen::Matrix<T, 3, 1>> r(residual);
    r = u.cast<T>() * e;
    return true;
  }

  Eigen::Vector2d z_t;
  double z_theta;
  Eigen::Matrix3d u;
};

/// EDGE_SE2_XY (types_slam2d/edge_se2_xy.h): e = R^T (l - t) - z, residual U e.
struct Se2XyCost {
  Se2XyCost(const Eigen::Vector2d& z, const Eigen::Matrix2d& sqrt_info) : z(z), u(sqrt_info) {}

  template <typename T>
  bool operator()(const T* x, const T* l, T* residual) const {
    using std::cos;
    using std::sin;
    const T c = cos(x[2]), s = sin(x[2]);
    const T dx = l[0] - x[0], dy = l[1] - x[1];
    Eigen::Matrix<T, 2, 1> e;
    e[0] = c * dx + s * dy - T(z.x());
    e[1] = -s * dx + c * dy - T(z.y());
    Eigen::Map<Eigen::Matrix<T, 2, 1>> r(residual);
    r = u.cast<T>() * e;
    return true;
  }

  Eigen::Vector2d z;
  Eigen::Matrix2d u;
};

/// EDGE_SE3:QUAT (types_slam3d/edges.h): e = compact(Z^-1 (X_i^-1 X_j)), the translation and
/// the vector part of the quaternion with a non-negative scalar part; residual U e. A pose's
/// parameter block is x y z qx qy qz qw (its .g2o numbers), on Ceres' product manifold of
/// R^3 and Eigen's quaternion.
struct Se3Cost {
  Se3Cost(const geometry::SE3& z, const Eigen::Matrix<double, 6, 6>& sqrt_info)
      : z_q(z.so3().quaternion()), z_t(z.translation()), u(sqrt_info) {}

  template <typename T>
  bool operator()(const T* xi, const T* xj, T* residual) const {
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> ti(xi), tj(xj);
    const Eigen::Map<const Eigen::Quaternion<T>> qi(xi + 3), qj(xj + 3);
    const Eigen::Quaternion<T> zq_inv = z_q.conjugate().cast<T>();
    Eigen::Quaternion<T> dq = zq_inv * (qi.conjugate() * qj);
    const Eigen::Matrix<T, 3, 1> dt = zq_inv * (qi.conjugate() * (tj - ti) - z_t.cast<T>());
    if (dq.w() < T(0)) dq.coeffs() = -dq.coeffs();
    Eigen::Matrix<T, 6, 1> e;
    e << dt, dq.vec();
    Eigen::Map<Eigen::Matrix<T, 6, 1>> r(residual);
    r = u.cast<T>() * e;
    return true;
  }

  Eigen::Quaterniond z_q;
  Eigen::Vector3d z_t;
  Eigen::Matrix<double, 6, 6> u;
};

/// Upper Cholesky factor U of a positive definite information matrix: U^T U = Omega.
template <int N>
Eigen::Matrix<double, N, N> upperFactor(const Eigen::Matrix<double, N, N>& omega) {
  return omega.llt().matrixU();
}

struct CeresRun {
  ceres::Solver::Summary summary;
  double build_s = 0.0;
  double solve_s = 0.0;
  double target_s = -1.0;  ///< time into Solve() of the first iterate at or below the target
};

/// Records when Ceres' chi2 (2 x cost) first reaches the target.
class TargetCallback final : public ceres::IterationCallback {
 public:
  TargetCallback(double target, double* seconds) : target_(target), seconds_(seconds) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    if (*seconds_ < 0 && 2.0 * s.cost <= target_) *seconds_ = s.cumulative_time_in_seconds;
    return ceres::SOLVER_CONTINUE;
  }

 private:
  double target_;
  double* seconds_;
};

/// Builds the Ceres problem from the graph's current estimates, solves it and writes the
/// result back into the graph.
CeresRun solveWithCeres(Graph& graph, const TypeRegistry& types, ceres::Solver::Options options,
                        double target) {
  CeresRun run;
  TargetCallback callback(target, &run.target_s);
  options.callbacks.push_back(&callback);
  const auto build_start = bench::Clock::now();
  std::map<VertexId, std::vector<double>> params;
  auto block = [&](const Vertex& v) -> double* {
    auto [it, inserted] = params.try_emplace(v.id());
    if (inserted) {
      it->second.resize(static_cast<std::size_t>(v.estimateDataDimension()));
      v.getEstimateData(it->second.data());
    }
    return it->second.data();
  };
  ceres::Problem problem;
  for (const auto& edge : graph.edges()) {
    if (const auto* e = dynamic_cast<const EdgeSE2*>(edge.get())) {
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<Se2Cost, 3, 3, 3>(
                                   new Se2Cost(e->measurement(), upperFactor<3>(e->information()))),
                               nullptr, block(*e->vertex(0)), block(*e->vertex(1)));
    } else if (const auto* e = dynamic_cast<const EdgeSE2XY*>(edge.get())) {
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<Se2XyCost, 2, 3, 2>(new Se2XyCost(
                                   e->measurement(), upperFactor<2>(e->information()))),
                               nullptr, block(*e->vertex(0)), block(*e->vertex(1)));
    } else if (const auto* e = dynamic_cast<const EdgeSE3*>(edge.get())) {
      double* pi = block(*e->vertex(0));
      double* pj = block(*e->vertex(1));
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<Se3Cost, 6, 7, 7>(
                                   new Se3Cost(e->measurement(), upperFactor<6>(e->information()))),
                               nullptr, pi, pj);
      for (double* p : {pi, pj}) {
        if (!problem.HasManifold(p)) {
          problem.SetManifold(p, new ceres::ProductManifold<ceres::EuclideanManifold<3>,
                                                            ceres::EigenQuaternionManifold>());
        }
      }
    } else {
      const std::string* tag = types.tagOf(*edge);
      throw bench::BadInput(
          "ceres_compare handles EDGE_SE2, EDGE_SE2_XY and EDGE_SE3:QUAT only, not " +
          (tag ? *tag : std::string("an unregistered edge type")) + " (edge of vertex " +
          std::to_string(edge->vertexId(0)) + ")");
    }
  }
  for (auto& [id, p] : params) {
    if (graph.vertex(id)->fixed()) problem.SetParameterBlockConstant(p.data());
  }
  run.build_s = bench::secondsSince(build_start);
  const auto solve_start = bench::Clock::now();
  ceres::Solve(options, &problem, &run.summary);
  run.solve_s = bench::secondsSince(solve_start);
  for (const auto& [id, p] : params) graph.vertex(id)->setEstimateData(p.data());
  return run;
}

}  // namespace

int main(int argc, char** argv) {
  bench::Args args(argc, argv, kUsage);
  const int repeats = args.integer("repeats", 1, 1);
  const int threads = args.integer("threads", 1, 1);
  const int max_iterations = args.integer("max-iterations", 100, 1);
  const double check_rel = args.number("check-rel", -1.0);
  // Time to the solution: the first iterate whose chi2 is at or below --target.
  const double target = args.number("target", -1.0);
  args.finish();
  args.skipIfAbsent();
  std::printf("openmp=%s\n", bench::serialiseOpenMp());
  const bench::Registries registries;
  const TypeRegistry& types = registries.types;
  const SolverRegistry& solvers = registries.solvers;
  return bench::guardedMain([&]() -> int {
    io::LoadResult loaded = bench::loadInitialised(args.file(), types);
    Graph& graph = loaded.graph;
    // The same gauge for both: the file's fixed vertices, else the lowest id.
    const Vertex* gauge = fixGaugeIfFree(graph);
    const auto initial = bench::saveEstimates(graph);
    const double initial_chi2 = graph.chi2();

    ceres::Solver::Options options;
    options.minimizer_type = ceres::TRUST_REGION;
    options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
    options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    options.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
    options.max_num_iterations = max_iterations;
    // graphslam's default relative chi2 decrease
    options.function_tolerance = Optimizer::Options{}.function_tolerance;
    options.gradient_tolerance = 1e-10;
    options.parameter_tolerance = 1e-10;
    options.num_threads = threads;
    options.logging_type = ceres::SILENT;
    options.minimizer_progress_to_stdout = false;

    std::vector<double> ours_s, ceres_s, ceres_build_s, ours_target_s, ceres_target_s;
    Summary ours;
    double ours_chi2 = 0.0, ceres_chi2 = 0.0;
    CeresRun ceres_run;
    for (int r = 0; r < repeats; ++r) {
      bench::restoreEstimates(graph, initial);
      Optimizer::Options ours_options;
      ours_options.threads = threads;
      double reached = initial_chi2 <= target ? 0.0 : -1.0;
      const auto start = bench::Clock::now();
      ours_options.callback = [&](const IterationStats& st) {
        if (reached < 0 && st.chi2 <= target) reached = bench::secondsSince(start);
      };
      Optimizer optimizer(graph, solvers, ours_options);
      ours = optimizer.optimize();
      ours_s.push_back(bench::secondsSince(start));
      ours_chi2 = graph.chi2();
      ours_target_s.push_back(reached);

      bench::restoreEstimates(graph, initial);
      ceres_run = solveWithCeres(graph, types, options, target);
      ceres_s.push_back(ceres_run.solve_s);
      ceres_build_s.push_back(ceres_run.build_s);
      if (target >= 0.0 && ceres_run.target_s < 0) {
        // Stopped by its tolerances above the target: the time to reach it is that of a
        // run with tolerances that do not stop it first (the iterates are the same).
        // (Re-solves from the start, then repeats the timed run so `graph` holds its result.)
        ceres::Solver::Options tight = options;
        tight.function_tolerance = tight.gradient_tolerance = tight.parameter_tolerance = 1e-15;
        bench::restoreEstimates(graph, initial);
        const CeresRun again = solveWithCeres(graph, types, tight, target);
        ceres_target_s.push_back(again.target_s);
        bench::restoreEstimates(graph, initial);
        ceres_run = solveWithCeres(graph, types, options, target);
      } else {
        ceres_target_s.push_back(ceres_run.target_s);
      }
      ceres_chi2 = graph.chi2();
    }
    const auto& cs = ceres_run.summary;
    std::printf("file=%s\n", args.file().c_str());
    std::printf("setup initial_chi2=%.17g gauge=%s repeats=%d threads=%d\n", initial_chi2,
                gauge ? std::to_string(gauge->id()).c_str() : "file", repeats, threads);
    std::printf("graphslam status=%s algorithm=%s solver=%s iterations=%d chi2=%.17g time_s=%.6g\n",
                toString(ours.status), toString(ours.algorithm), ours.linear_solver.c_str(),
                ours.iterations, ours_chi2, bench::median(ours_s));
    std::printf(
        "ceres version=%s termination=%s iterations=%d successful=%d chi2=%.17g "
        "ceres_cost_x2=%.17g time_s=%.6g build_s=%.6g linear_solver_s=%.6g "
        "residual_eval_s=%.6g jacobian_eval_s=%.6g threads=%d ordering=ceres-default\n",
        CERES_VERSION_STRING, ceres::TerminationTypeToString(cs.termination_type),
        cs.num_successful_steps + cs.num_unsuccessful_steps, cs.num_successful_steps, ceres_chi2,
        2.0 * cs.final_cost, bench::median(ceres_s), bench::median(ceres_build_s),
        cs.linear_solver_time_in_seconds, cs.residual_evaluation_time_in_seconds,
        cs.jacobian_evaluation_time_in_seconds, cs.num_threads_used);
    const double rel = std::abs(ceres_chi2 - ours_chi2) / std::max(std::abs(ours_chi2), 1e-300);
    std::printf("compare chi2_rel_diff=%.3e speed_ratio=%.4g\n", rel,
                bench::median(ceres_s) / bench::median(ours_s));
    if (target >= 0.0) {
      // -1: the target was not reached. A run reaches it in every repeat or in none (the
      // iterates are deterministic), so the median is of like values.
      const double ours_t = bench::median(ours_target_s);
      const double ceres_t = bench::median(ceres_target_s);
      std::printf("target chi2=%.17g graphslam_s=%.6g ceres_s=%.6g speed_ratio=%.4g\n", target,
                  ours_t, ceres_t, ours_t > 0 && ceres_t > 0 ? ceres_t / ours_t : -1.0);
    }
    if (check_rel >= 0.0 && !(rel <= check_rel)) {
      std::fprintf(stderr, "final chi2 differ: graphslam %.17g, Ceres %.17g (relative %.3e > %g)\n",
                   ours_chi2, ceres_chi2, rel, check_rel);
      return 1;
    }
    return 0;
  });
}
