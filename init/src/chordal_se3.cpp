// SPDX-License-Identifier: MIT
#include "graphslam/init/chordal_se3.h"

#include <Eigen/SVD>
#include <Eigen/SparseCholesky>
#include <array>
#include <chrono>
#include <cmath>
#include <numeric>
#include <unordered_map>
#include <vector>

#include "graphslam/diagnostics/information.h"
#include "graphslam/types_slam3d/edges.h"

namespace graphslam::init {

namespace {

using types_slam3d::EdgeSE3;
using types_slam3d::SE3;
using types_slam3d::VertexSE3;

/// The poses reached by active relative-pose edges, in id order, and those edges.
struct Problem3d {
  std::vector<VertexSE3*> poses;
  std::vector<const EdgeSE3*> edges;
  std::vector<std::pair<int, int>> ends;  ///< pose indices of each edge
  std::vector<char> anchored;             ///< per pose: its estimate is kept
};

Problem3d collect(Graph& graph) {
  Problem3d p;
  std::unordered_map<VertexId, int> index;
  for (const auto& e : graph.edges()) {
    if (const auto* se3 = dynamic_cast<const EdgeSE3*>(e.get()); se3 && se3->active()) {
      p.edges.push_back(se3);
      for (VertexId id : se3->vertexIds()) index.emplace(id, -1);
    }
  }
  for (const auto& [id, v] : graph.vertices()) {
    auto it = index.find(id);
    if (it == index.end()) continue;
    it->second = static_cast<int>(p.poses.size());
    p.poses.push_back(static_cast<VertexSE3*>(v.get()));
  }
  for (const EdgeSE3* e : p.edges)
    p.ends.emplace_back(index[e->vertexId(0)], index[e->vertexId(1)]);
  return p;
}

/// Fixed poses, and in each connected group without one its lowest-id pose.
std::vector<char> anchors(const Problem3d& p) {
  const int n = static_cast<int>(p.poses.size());
  std::vector<int> parent(static_cast<std::size_t>(n));
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  for (const auto& [i, j] : p.ends) {
    const int a = find(i), b = find(j);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);  // the root is the lowest index
  }
  std::vector<char> anchored(static_cast<std::size_t>(n), 0), group_fixed(anchored);
  for (int i = 0; i < n; ++i) {
    if (p.poses[i]->fixed()) anchored[i] = group_fixed[find(i)] = 1;
  }
  for (int i = 0; i < n; ++i) {
    if (find(i) == i && !group_fixed[i]) anchored[i] = 1;  // the group's lowest id
  }
  return anchored;
}

/// Columns of the free poses (block size `d`), -1 for anchored ones; `count` set to their
/// number of blocks.
std::vector<int> freeColumns(const std::vector<char>& anchored, int& count) {
  std::vector<int> col(anchored.size(), -1);
  count = 0;
  for (std::size_t i = 0; i < anchored.size(); ++i) {
    if (!anchored[i]) col[i] = count++;
  }
  return col;
}

/// Solves the SPD system `h` x = `rhs` (several columns), of unknowns in blocks of
/// `block`, with `solver` (Eigen's simplicial LDL^T when null); false when it is singular.
bool solveSpd(const Eigen::SparseMatrix<double>& h, const Eigen::MatrixXd& rhs, int block,
              LinearSolver* solver, Eigen::MatrixXd& x) {
  if (!solver) {
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(h);
    if (ldlt.info() != Eigen::Success) return false;
    x = ldlt.solve(rhs);
    return ldlt.info() == Eigen::Success && x.allFinite();
  }
  // The solver interface's form: the upper triangle of blocks, each stored block complete
  // (diagonal blocks full).
  Eigen::SparseMatrix<double> upper = h;
  upper.prune([block](Eigen::Index r, Eigen::Index c, double) { return r / block <= c / block; });
  upper.makeCompressed();
  const auto n = static_cast<int>(upper.cols());
  const std::vector<int> col_ptr(upper.outerIndexPtr(), upper.outerIndexPtr() + n + 1);
  const std::vector<int> rows(upper.innerIndexPtr(), upper.innerIndexPtr() + upper.nonZeros());
  std::vector<int> block_starts;
  for (int c = 0; c <= n; c += block) block_starts.push_back(c);
  SparseStructure st;
  st.n = n;
  st.col_ptr = col_ptr.data();
  st.row_idx = rows.data();
  st.block_starts = block_starts.data();
  st.num_blocks = n / block;
  if (!solver->analyze(st).ok() || !solver->factorize(upper.valuePtr()).ok()) return false;
  x.resize(n, rhs.cols());
  for (Eigen::Index c = 0; c < rhs.cols(); ++c) {
    const Eigen::VectorXd b = rhs.col(c);
    if (!solver->solve(b.data(), x.col(c).data()).ok()) return false;
  }
  return x.allFinite();
}

/// Step 1: the rotations of the free poses (row k of R_i is unknown x_i^k; R_j = R_i R_ij
/// is x_j^k = R_ij^T x_i^k for every row k).
bool solveRotations(const Problem3d& p, const std::vector<int>& col, int free, LinearSolver* solver,
                    std::vector<Eigen::Matrix3d>& rotations) {
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(3 * free, 3);
  auto addBlock = [&](int r, int c, const Eigen::Matrix3d& m) {
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) triplets.emplace_back(3 * r + a, 3 * c + b, m(a, b));
  };
  for (std::size_t k = 0; k < p.edges.size(); ++k) {
    const auto [i, j] = p.ends[k];
    const double kappa = isotropicWeight(p.edges[k]->information().bottomRightCorner<3, 3>()) / 2.0;
    const Eigen::Matrix3d rij = p.edges[k]->measurement().rotation();
    // Residual x_j - R_ij^T x_i: blocks kappa I, kappa I and -kappa R_ij (row i, column j).
    const int ci = col[i], cj = col[j];
    if (ci >= 0) addBlock(ci, ci, kappa * Eigen::Matrix3d::Identity());
    if (cj >= 0) addBlock(cj, cj, kappa * Eigen::Matrix3d::Identity());
    if (ci >= 0 && cj >= 0) {
      addBlock(ci, cj, -kappa * rij);
      addBlock(cj, ci, -kappa * rij.transpose());
    } else if (ci >= 0) {  // x_j known: rhs_i += kappa R_ij x_j (rows of R_j as columns)
      rhs.middleRows<3>(3 * ci) += kappa * rij * p.poses[j]->estimate().rotation().transpose();
    } else if (cj >= 0) {  // x_i known: rhs_j += kappa R_ij^T x_i
      rhs.middleRows<3>(3 * cj) +=
          kappa * rij.transpose() * p.poses[i]->estimate().rotation().transpose();
    }
  }
  Eigen::SparseMatrix<double> h(3 * free, 3 * free);
  h.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::MatrixXd x;
  if (!solveSpd(h, rhs, 3, solver, x)) return false;
  rotations.resize(static_cast<std::size_t>(free));
  for (int c = 0; c < free; ++c) {
    // Column k of the block holds row k of R: the block is R^T. Nearest rotation by SVD.
    const Eigen::Matrix3d m = x.middleRows<3>(3 * c).transpose();
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
    d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
    rotations[static_cast<std::size_t>(c)] = svd.matrixU() * d * svd.matrixV().transpose();
  }
  return true;
}

/// Step 2: the translations of the free poses, t_j - t_i = R_i t_ij (a weighted graph
/// Laplacian with three right-hand sides).
bool solveTranslations(const Problem3d& p, const std::vector<int>& col, int free,
                       LinearSolver* solver, const std::vector<Eigen::Matrix3d>& rotations,
                       std::vector<Eigen::Vector3d>& translations) {
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(free, 3);
  auto rotation = [&](int i) -> Eigen::Matrix3d {
    return col[i] >= 0 ? rotations[static_cast<std::size_t>(col[i])]
                       : p.poses[i]->estimate().rotation();
  };
  for (std::size_t k = 0; k < p.edges.size(); ++k) {
    const auto [i, j] = p.ends[k];
    const double tau = isotropicWeight(p.edges[k]->information().topLeftCorner<3, 3>());
    const Eigen::Vector3d d = rotation(i) * p.edges[k]->measurement().translation();
    // Residual a_i t_i + a_j t_j - d with a_i = -1, a_j = 1; known translations move to
    // the right-hand side.
    const std::array<int, 2> v = {i, j};
    const std::array<double, 2> a = {-1.0, 1.0};
    Eigen::RowVector3d known = d.transpose();
    for (int s = 0; s < 2; ++s) {
      if (col[v[s]] < 0) known -= a[s] * p.poses[v[s]]->estimate().translation().transpose();
    }
    for (int s = 0; s < 2; ++s) {
      const int c = col[v[s]];
      if (c < 0) continue;
      rhs.row(c) += tau * a[s] * known;
      for (int u = 0; u < 2; ++u) {
        if (col[v[u]] >= 0) triplets.emplace_back(c, col[v[u]], tau * a[s] * a[u]);
      }
    }
  }
  Eigen::SparseMatrix<double> h(free, free);
  h.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::MatrixXd x;
  if (!solveSpd(h, rhs, 1, solver, x)) return false;
  translations.resize(static_cast<std::size_t>(free));
  for (int c = 0; c < free; ++c) translations[static_cast<std::size_t>(c)] = x.row(c).transpose();
  return true;
}

/// Places every non-fixed VERTEX_TRACKXYZ that an EDGE_SE3_TRACKXYZ observes from a placed
/// pose, from its first such observation: p = X P z. Returns the number placed.
std::size_t placePoints(Graph& graph) {
  std::size_t placed = 0;
  for (const auto& [id, v] : graph.vertices()) {
    auto* point = dynamic_cast<types_slam3d::VertexPointXYZ*>(v.get());
    if (point == nullptr || point->fixed()) continue;
    for (const Edge* e : point->edges()) {
      const auto* obs = dynamic_cast<const types_slam3d::EdgeSE3PointXYZ*>(e);
      if (obs == nullptr || !obs->active() || obs->vertexId(1) != id) continue;
      const auto& pose = static_cast<const VertexSE3&>(*obs->vertex(0));
      point->setEstimate(pose.estimate() *
                         (obs->typedParameter<0>().offset() * obs->measurement()));
      ++placed;
      break;
    }
  }
  return placed;
}

}  // namespace

InitializationReport initializeChordal3d(Graph& graph) {
  return initializeChordal3d(graph, nullptr);
}

InitializationReport initializeChordal3d(Graph& graph, LinearSolver* solver) {
  const auto start = std::chrono::steady_clock::now();
  InitializationReport report;
  Problem3d p = collect(graph);
  if (p.poses.empty()) {
    report.message = "no EDGE_SE3:QUAT in the graph: nothing to initialise";
    return report;
  }
  const std::vector<char> anchored = anchors(p);
  int free = 0;
  const std::vector<int> col = freeColumns(anchored, free);
  std::vector<Eigen::Matrix3d> rotations;
  std::vector<Eigen::Vector3d> translations;
  if (free > 0 && (!solveRotations(p, col, free, solver, rotations) ||
                   !solveTranslations(p, col, free, solver, rotations, translations))) {
    report.message = "the chordal system is singular: initial guess kept";
    report.failed = true;
    return report;
  }
  for (std::size_t i = 0; i < p.poses.size(); ++i) {
    if (col[i] < 0) continue;
    const auto c = static_cast<std::size_t>(col[i]);
    p.poses[i]->setEstimate(SE3(geometry::SO3::fromMatrix(rotations[c]), translations[c]));
    ++report.poses;
  }
  report.landmarks = placePoints(graph);
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace graphslam::init
