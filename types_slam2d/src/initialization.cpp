// SPDX-License-Identifier: MIT
#include "graphslam/types_slam2d/initialization.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <queue>
#include <unordered_map>
#include <vector>

#include "graphslam/types_slam2d/edge_prior_se2.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/edge_se2_xy.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"

namespace graphslam::types_slam2d {

namespace {

using SpMat = Eigen::SparseMatrix<double>;
using Triplets = std::vector<Eigen::Triplet<double>>;

struct PoseNode {
  VertexSE2* vertex;
  std::vector<std::pair<const EdgeSE2*, int>> links;  // edge, index of the other pose
  bool anchored = false;                              // fixed vertex or prior
};

/// Solves symmetric positive definite systems (both triangles, unknowns in blocks of
/// `block` scalars) with `solver`, or with Eigen's simplicial LDL^T when it is null. A
/// system with the pattern of the previous one reuses its symbolic analysis (ordering and
/// all): a pose graph's orientation and position systems share theirs.
class SpdSolver {
 public:
  explicit SpdSolver(LinearSolver* solver) : solver_(solver) {}

  /// False on failure.
  bool solve(const SpMat& a, int block, const Eigen::VectorXd& b, Eigen::VectorXd& x) {
    if (!solver_) {
      if (!samePattern(a)) ldlt_.analyzePattern(a);
      ldlt_.factorize(a);
      if (ldlt_.info() != Eigen::Success) return false;
      x = ldlt_.solve(b);
      return ldlt_.info() == Eigen::Success && x.allFinite();
    }
    // The solver interface: upper triangle in CSC, every stored block complete (its
    // structural zeros too), the same rows in every column of a block.
    const int n = static_cast<int>(a.cols());
    std::vector<int> col_ptr(static_cast<std::size_t>(n) + 1, 0);
    std::vector<int> row_idx;
    std::vector<double> values;
    std::vector<int> blocks;                                 // row blocks of a block column
    std::vector<int> slot(static_cast<std::size_t>(n), -1);  // scalar row -> value index
    for (int c0 = 0; c0 < n; c0 += block) {
      blocks.clear();
      for (int c = c0; c < c0 + block; ++c) {
        for (SpMat::InnerIterator it(a, c); it; ++it) {
          const int rb = static_cast<int>(it.row()) / block;
          if (rb <= c0 / block) blocks.push_back(rb);
        }
      }
      std::sort(blocks.begin(), blocks.end());
      blocks.erase(std::unique(blocks.begin(), blocks.end()), blocks.end());
      for (int c = c0; c < c0 + block; ++c) {
        for (int rb : blocks) {
          for (int r = rb * block; r < (rb + 1) * block; ++r) {
            slot[r] = static_cast<int>(row_idx.size());
            row_idx.push_back(r);
          }
        }
        values.resize(row_idx.size(), 0.0);
        for (SpMat::InnerIterator it(a, c); it; ++it) {
          const int r = static_cast<int>(it.row());
          if (r / block <= c0 / block) values[static_cast<std::size_t>(slot[r])] = it.value();
        }
        col_ptr[c + 1] = static_cast<int>(row_idx.size());
      }
    }
    x.resize(n);
    if (!analyzed_ || block != block_ || col_ptr != col_ptr_ || row_idx != row_idx_) {
      // The solver reads these arrays until its next analysis: they live here.
      col_ptr_ = std::move(col_ptr);
      row_idx_ = std::move(row_idx);
      block_ = block;
      block_starts_.clear();
      for (int c = 0; c <= n; c += block) block_starts_.push_back(c);
      SparseStructure st;
      st.n = n;
      st.col_ptr = col_ptr_.data();
      st.row_idx = row_idx_.data();
      st.block_starts = block_starts_.data();
      st.num_blocks = n / block;
      analyzed_ = solver_->analyze(st).ok();
      if (!analyzed_) return false;
    }
    return solver_->factorize(values.data()).ok() && solver_->solve(b.data(), x.data()).ok() &&
           x.allFinite();
  }

 private:
  bool samePattern(const SpMat& a) {
    const auto* p = a.outerIndexPtr();
    const auto* i = a.innerIndexPtr();
    const auto cols = static_cast<std::size_t>(a.cols());
    const bool same = analyzed_ && col_ptr_.size() == cols + 1 &&
                      std::equal(p, p + cols + 1, col_ptr_.begin()) &&
                      std::equal(i, i + p[cols], row_idx_.begin(), row_idx_.end());
    if (!same) {
      col_ptr_.assign(p, p + cols + 1);
      row_idx_.assign(i, i + p[cols]);
      analyzed_ = true;
    }
    return same;
  }

  LinearSolver* solver_;
  Eigen::SimplicialLDLT<SpMat> ldlt_;
  std::vector<int> col_ptr_, row_idx_, block_starts_;
  int block_ = 0;
  bool analyzed_ = false;
};

}  // namespace

InitializationReport initializeGlobal(Graph& graph) { return initializeGlobal(graph, nullptr); }

InitializationReport initializeGlobal(Graph& graph, LinearSolver* solver) {
  const auto t0 = std::chrono::steady_clock::now();
  InitializationReport report;
  SpdSolver spd(solver);

  // Poses reached by relative-pose edges, in id order (the optimizer's order of blocks:
  // large graphs then share one fill-reducing ordering with it).
  std::vector<const EdgeSE2*> relative;
  std::vector<VertexSE2*> pose_vertices;
  for (const auto& e : graph.edges()) {
    if (const auto* se2 = dynamic_cast<const EdgeSE2*>(e.get())) {
      relative.push_back(se2);
      for (std::size_t k = 0; k < 2; ++k) {
        pose_vertices.push_back(static_cast<VertexSE2*>(graph.vertex(se2->vertex(k)->id())));
      }
    }
  }
  std::sort(pose_vertices.begin(), pose_vertices.end(),
            [](const VertexSE2* a, const VertexSE2* b) { return a->id() < b->id(); });
  pose_vertices.erase(std::unique(pose_vertices.begin(), pose_vertices.end()), pose_vertices.end());
  std::unordered_map<const Vertex*, int> pose_index;
  pose_index.reserve(pose_vertices.size());
  std::vector<PoseNode> poses;
  poses.reserve(pose_vertices.size());
  for (VertexSE2* v : pose_vertices) {
    pose_index.emplace(v, static_cast<int>(poses.size()));
    poses.push_back({v, {}, v->fixed()});
  }
  for (const EdgeSE2* se2 : relative) {
    const int i = pose_index.at(se2->vertex(0));
    const int j = pose_index.at(se2->vertex(1));
    poses[i].links.emplace_back(se2, j);
    poses[j].links.emplace_back(se2, i);
  }
  std::vector<const EdgePriorSE2*> priors;
  std::vector<const EdgeSE2XY*> observations;
  for (const auto& e : graph.edges()) {
    if (const auto* prior = dynamic_cast<const EdgePriorSE2*>(e.get())) {
      auto it = pose_index.find(prior->vertex(0));
      if (it == pose_index.end()) continue;
      poses[it->second].anchored = true;
      priors.push_back(prior);
    } else if (const auto* obs = dynamic_cast<const EdgeSE2XY*>(e.get())) {
      if (pose_index.count(obs->vertex(0))) observations.push_back(obs);
    }
  }
  const int n = static_cast<int>(poses.size());
  if (n == 0) {
    report.message = "no EDGE_SE2 in the graph: nothing to initialise";
    return report;
  }

  // Connected groups (over EDGE_SE2), flooded from anchored poses first, then in id order
  // (poses are numbered by id): a group reached from an unanchored pose has no anchor and
  // holds that pose, its lowest id, where it is (its gauge).
  std::vector<char> gauge(static_cast<std::size_t>(n), 0);
  std::vector<int> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  std::stable_partition(order.begin(), order.end(), [&](int i) { return poses[i].anchored; });
  std::vector<char> reached(static_cast<std::size_t>(n), 0);
  for (int s : order) {
    if (reached[s]) continue;
    if (!poses[s].anchored) gauge[s] = 1;
    std::queue<int> q;
    q.push(s);
    reached[s] = 1;
    while (!q.empty()) {
      const int u = q.front();
      q.pop();
      for (const auto& [edge, v] : poses[u].links) {
        if (!reached[v]) {
          reached[v] = 1;
          q.push(v);
        }
      }
    }
  }

  // Step 1: orientations by chordal relaxation. Each pose's rotation is the unit vector
  // r_i = (cos theta_i, sin theta_i), relaxed to any vector of R^2; an edge asks for
  // r_j = R(dtheta_ij) r_i and a prior for r_i = r(z), weighted by the angular
  // information. The linear least-squares solution, normalised, gives the angles; no 2*pi
  // ambiguity arises. Unknowns: every pose that is neither fixed nor a gauge.
  std::vector<int> var(static_cast<std::size_t>(n), -1);
  int nv = 0;
  for (int i = 0; i < n; ++i) {
    if (!poses[i].vertex->fixed() && !gauge[i]) var[i] = nv++;
  }
  std::vector<double> theta(static_cast<std::size_t>(n), 0.0);
  for (int i = 0; i < n; ++i) theta[i] = poses[i].vertex->estimate().angle();
  {
    Triplets trip;
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(2 * nv);
    auto unit = [](double t) { return Eigen::Vector2d(std::cos(t), std::sin(t)); };
    auto add_diagonal = [&](int a, double w) {  // w I, stored as a full 2x2 block
      trip.emplace_back(2 * a, 2 * a, w);
      trip.emplace_back(2 * a + 1, 2 * a + 1, w);
      trip.emplace_back(2 * a, 2 * a + 1, 0.0);
      trip.emplace_back(2 * a + 1, 2 * a, 0.0);
    };
    for (int u = 0; u < n; ++u) {
      for (const auto& [edge, v] : poses[u].links) {
        if (edge->vertex(0) != poses[u].vertex) continue;  // each edge once, from its first pose
        const double w = edge->information()(2, 2);
        const Eigen::Matrix2d q = rotation2(edge->measurement().angle());
        const int a = var[u], b = var[v];
        // w |r_v - q r_u|^2: blocks (u,u) = (v,v) = w I, (u,v) = -w q^T, (v,u) = -w q.
        if (a >= 0) add_diagonal(a, w);
        if (b >= 0) add_diagonal(b, w);
        if (a >= 0 && b >= 0) {
          for (int r = 0; r < 2; ++r) {
            for (int c = 0; c < 2; ++c) {
              trip.emplace_back(2 * a + r, 2 * b + c, -w * q(c, r));
              trip.emplace_back(2 * b + r, 2 * a + c, -w * q(r, c));
            }
          }
        } else if (a >= 0) {
          rhs.segment<2>(2 * a) += w * q.transpose() * unit(theta[v]);
        } else if (b >= 0) {
          rhs.segment<2>(2 * b) += w * q * unit(theta[u]);
        }
      }
    }
    for (const EdgePriorSE2* prior : priors) {
      const int i = pose_index.at(prior->vertex(0));
      if (var[i] < 0) continue;
      const double w = prior->information()(2, 2);
      add_diagonal(var[i], w);
      rhs.segment<2>(2 * var[i]) += w * unit(prior->measurement().angle());
    }
    SpMat a(2 * nv, 2 * nv);
    a.setFromTriplets(trip.begin(), trip.end());
    Eigen::VectorXd r;
    if (nv > 0 && !spd.solve(a, 2, rhs, r)) {
      report.message = "orientation system is singular: initial estimates kept";
      return report;
    }
    for (int i = 0; i < n; ++i) {
      if (var[i] >= 0) theta[i] = std::atan2(r[2 * var[i] + 1], r[2 * var[i]]);
    }
  }

  // Step 2: translations of poses and positions of landmarks, orientations held.
  std::unordered_map<const Vertex*, int> lm_var;
  std::vector<VertexXY*> landmarks;
  for (const EdgeSE2XY* obs : observations) {
    const Vertex* l = obs->vertex(1);
    if (l->fixed() || lm_var.count(l)) continue;
    lm_var.emplace(l, nv + static_cast<int>(landmarks.size()));
    landmarks.push_back(static_cast<VertexXY*>(graph.vertex(l->id())));
  }
  const int nt = nv + static_cast<int>(landmarks.size());
  {
    Triplets trip;
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(2 * nt);
    // Adds the residual (x_b - x_a) - d with 2x2 weight W; -1 marks a known position.
    auto add = [&](int a, const Eigen::Vector2d& xa, int b, const Eigen::Vector2d& xb,
                   const Eigen::Vector2d& d, const Eigen::Matrix2d& w) {
      for (int r = 0; r < 2; ++r) {
        for (int c = 0; c < 2; ++c) {
          if (a >= 0) trip.emplace_back(2 * a + r, 2 * a + c, w(r, c));
          if (b >= 0) trip.emplace_back(2 * b + r, 2 * b + c, w(r, c));
          if (a >= 0 && b >= 0) {
            trip.emplace_back(2 * a + r, 2 * b + c, -w(r, c));
            trip.emplace_back(2 * b + r, 2 * a + c, -w(r, c));
          }
        }
      }
      if (a >= 0)
        rhs.segment<2>(2 * a) +=
            -w * d + (b < 0 ? Eigen::Vector2d(w * xb) : Eigen::Vector2d::Zero());
      if (b >= 0)
        rhs.segment<2>(2 * b) +=
            w * d + (a < 0 ? Eigen::Vector2d(w * xa) : Eigen::Vector2d::Zero());
    };
    auto pos = [&](int i) { return poses[i].vertex->estimate().translation(); };
    for (int u = 0; u < n; ++u) {
      for (const auto& [edge, v] : poses[u].links) {
        if (edge->vertex(0) != poses[u].vertex) continue;
        const Eigen::Matrix2d r = rotation2(theta[u]) * edge->measurement().rotation();
        const Eigen::Matrix2d w = r * edge->information().topLeftCorner<2, 2>() * r.transpose();
        add(var[u], pos(u), var[v], pos(v), rotation2(theta[u]) * edge->measurement().translation(),
            w);
      }
    }
    for (const EdgeSE2XY* obs : observations) {
      const int i = pose_index.at(obs->vertex(0));
      const Vertex* l = obs->vertex(1);
      const int b = l->fixed() ? -1 : lm_var.at(l);
      const Eigen::Vector2d xl = static_cast<const VertexXY*>(l)->estimate();
      const Eigen::Matrix2d r = rotation2(theta[i]);
      const Eigen::Matrix2d w = r * obs->information() * r.transpose();
      add(var[i], pos(i), b, xl, r * obs->measurement(), w);
    }
    for (const EdgePriorSE2* prior : priors) {
      const int i = pose_index.at(prior->vertex(0));
      if (var[i] < 0) continue;
      const Eigen::Matrix2d r = prior->measurement().rotation();
      const Eigen::Matrix2d w = r * prior->information().topLeftCorner<2, 2>() * r.transpose();
      add(-1, Eigen::Vector2d::Zero(), var[i], Eigen::Vector2d::Zero(),
          prior->measurement().translation(), w);
    }
    SpMat a(2 * nt, 2 * nt);
    a.setFromTriplets(trip.begin(), trip.end());
    Eigen::VectorXd x;
    if (nt > 0 && !spd.solve(a, 2, rhs, x)) {
      report.message = "position system is singular: initial estimates kept";
      return report;
    }
    for (int i = 0; i < n; ++i) {
      if (var[i] < 0) continue;
      poses[i].vertex->setEstimate(SE2(x.segment<2>(2 * var[i]), theta[i]));
      ++report.poses;
    }
    for (std::size_t k = 0; k < landmarks.size(); ++k) {
      landmarks[k]->setEstimate(x.segment<2>(2 * (nv + static_cast<int>(k))));
      ++report.landmarks;
    }
  }
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return report;
}

}  // namespace graphslam::types_slam2d
