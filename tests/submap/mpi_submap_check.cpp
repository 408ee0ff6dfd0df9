// SPDX-License-Identifier: MIT
// Run under mpirun (ctest: Submap_Mpi.*): the submap solver across the ranks reaches the
// same optimum as in one process, and the ranks exchange the bytes it reports. Exit 0 on
// success, 1 with a message on rank 0 otherwise.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "graphslam/simulation/simulator.h"
#include "graphslam/simulation/simulator3d.h"
#include "graphslam/submap/mpi_solver.h"

using namespace graphslam;

namespace {

std::vector<double> allEstimates(const Graph& g) {
  std::vector<double> out;
  for (const auto& [id, v] : g.vertices()) {
    std::vector<double> x(static_cast<std::size_t>(v->estimateDataDimension()));
    v->getEstimateData(x.data());
    out.insert(out.end(), x.begin(), x.end());
  }
  return out;
}

Graph makeGraph(bool three_d) {
  if (three_d) {
    simulation::PoseGraph3dOptions o;
    o.num_poses = 600;
    return simulation::simulatePoseGraph3d(o).graph;
  }
  simulation::ManhattanOptions o;
  o.num_poses = 2000;
  o.num_landmarks = 100;
  o.seed = 3;
  return simulation::simulateManhattan(o).graph;
}

/// One case: `submaps` submaps over the ranks against one process; false on rank 0 when they
/// differ.
bool check(bool three_d, int submaps, int rank) {
  submap::Options options;
  options.partition.num_submaps = submaps;
  options.function_tolerance = 1e-14;
  options.max_iterations = 50;
  Graph distributed = makeGraph(three_d);
  const submap::Summary ms = submap::MpiSubmapSolver(distributed, options).optimize();
  if (rank != 0) return true;
  Graph local = makeGraph(three_d);
  const submap::Summary ls = submap::SubmapSolver(local, options).optimize();
  const auto a = allEstimates(distributed), b = allEstimates(local);
  double worst = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) worst = std::max(worst, std::abs(a[k] - b[k]));
  std::printf(
      "%s, %d submaps: chi2 %.12g (MPI) vs %.12g (one process), largest estimate "
      "difference %.3g, final gradient norm %.3g, %d iterations\n",
      three_d ? "3D sphere" : "2D Manhattan with landmarks", submaps, ms.final_chi2, ls.final_chi2,
      worst, ms.final_gradient_norm, ms.iterations);
  for (const auto& it : ms.per_iteration) {
    std::printf("  iter %d: chi2 %.10g, separator %zu vertices, %zu bytes communicated\n",
                it.iteration, it.chi2, it.separator_vertices, it.bytes_communicated);
  }
  const bool ok = ms.succeeded() && ls.succeeded() && ms.iterations == ls.iterations &&
                  std::abs(ms.final_chi2 - ls.final_chi2) <= 1e-9 * ls.final_chi2 &&
                  worst <= 1e-9 && ms.bytes_communicated > 0;
  if (!ok) std::printf("MISMATCH: %s\n%s\n", ms.report().c_str(), ls.report().c_str());
  return ok;
}

}  // namespace

int main(int argc, char** argv) {
  submap::MpiSession mpi(argc, argv);
  if (mpi.size() < 2 && mpi.rank() == 0) std::printf("note: one rank only\n");
  bool ok = check(false, 5, mpi.rank());
  ok = check(true, 4, mpi.rank()) && ok;
  return mpi.rank() == 0 && !ok ? EXIT_FAILURE : EXIT_SUCCESS;
}
