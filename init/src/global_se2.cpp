// SPDX-License-Identifier: MIT
#include "graphslam/init/global_se2.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <numeric>
#include <optional>
#include <unordered_map>
#include <vector>

#include "graphslam/types_slam2d/edge_prior_se2.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/edge_se2_xy.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"
#include "pair_system.h"

namespace graphslam::init {

using namespace graphslam::types_slam2d;

namespace {

using detail::PairSystem;
using detail::SpdSolver;

/// Adds the residual sum_k M_k x_k - c, weighted by w I, to `sys`: terms with an unknown
/// index < 0 are known values (moved to the right-hand side).
struct LinearTerm {
  int unknown;              ///< 2-vector unknown of the system, or -1
  Eigen::Matrix2d m;        ///< its coefficient
  Eigen::Vector2d known{};  ///< its value when unknown < 0
};
template <std::size_t K>
void addResidual(PairSystem& sys, const std::array<LinearTerm, K>& terms, double w) {
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (const LinearTerm& t : terms) {
    if (t.unknown < 0) c -= t.m * t.known;
  }
  for (std::size_t a = 0; a < K; ++a) {
    if (terms[a].unknown < 0) continue;
    sys.rhs().segment<2>(2 * terms[a].unknown) += w * terms[a].m.transpose() * c;
    for (std::size_t b = a; b < K; ++b) {
      if (terms[b].unknown < 0) continue;
      const Eigen::Matrix2d m = w * terms[a].m.transpose() * terms[b].m;
      if (b != a && terms[b].unknown == terms[a].unknown) {
        sys.add(terms[a].unknown, terms[a].unknown, m + m.transpose());  // one unknown twice
      } else {
        sys.add(terms[a].unknown, terms[b].unknown, m);
      }
    }
  }
}

/// (cos theta, sin theta): a rotation as a vector of R^2.
Eigen::Vector2d unitVector(double theta) { return {std::cos(theta), std::sin(theta)}; }

/// [v_x -v_y; v_y v_x]: R(theta) v = vecMatrix(v) unitVector(theta).
Eigen::Matrix2d vecMatrix(const Eigen::Vector2d& v) {
  Eigen::Matrix2d m;
  m << v.x(), -v.y(), v.y(), v.x();
  return m;
}

/// What the initialisation works on: the poses reached by relative-pose edges, in id order
/// (the optimizer's order of blocks: large graphs then share one fill-reducing ordering with
/// it), each edge's two pose indices, and the priors and landmark observations on them.
struct Problem {
  std::vector<VertexSE2*> poses;
  std::vector<const EdgeSE2*> relative;
  std::vector<std::pair<int, int>> ends;  ///< (first pose, second pose) of each relative edge
  std::vector<double> relative_weight;    ///< factor on each relative edge's information
  std::vector<std::pair<const EdgePriorSE2*, int>> priors;
  std::vector<std::pair<const EdgeSE2XY*, int>> observations;
  std::vector<double> observation_weight;  ///< factor on each observation's information
  std::vector<char> anchored;              ///< per pose: fixed, or has a prior
  [[nodiscard]] int size() const { return static_cast<int>(poses.size()); }
};

/// Step 1 of initializeGlobal with landmark observations (see there): orientations,
/// translations and landmarks in one linear system, the rotations relaxed to free vectors;
/// the weights are the angular information and the translational ones made isotropic (their
/// mean eigenvalue: the frame of r_i is not known yet). Updates theta of the free poses
/// (var >= 0); false when the system is singular.
bool jointOrientations(const Problem& p, const std::vector<int>& obs_landmark, int num_landmarks,
                       const std::vector<int>& var, int nv, std::vector<double>& theta,
                       SpdSolver& spd) {
  const auto& poses = p.poses;
  const auto& relative = p.relative;
  const auto& ends = p.ends;
  const auto& observations = p.observations;
  const auto& priors = p.priors;
  // Unknowns (2-vectors): t_i at var[i], r_i at nv + var[i], free landmarks from 2 nv.
  const int unknowns = 2 * nv + num_landmarks;
  std::vector<int> obs_lm(observations.size(), -1);
  for (std::size_t k = 0; k < observations.size(); ++k) {
    if (obs_landmark[k] >= 0) obs_lm[k] = 2 * nv + obs_landmark[k];
  }
  auto t_of = [&](int i) { return var[i]; };
  auto r_of = [&](int i) { return var[i] < 0 ? -1 : nv + var[i]; };
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(4 * relative.size() + 3 * observations.size());
  auto couple = [&](int a, int b) {
    if (a >= 0 && b >= 0 && a != b) pairs.emplace_back(a, b);
  };
  for (const auto& [u, v] : ends) {
    couple(t_of(v), t_of(u));
    couple(t_of(v), r_of(u));
    couple(t_of(u), r_of(u));
    couple(r_of(v), r_of(u));
  }
  for (std::size_t k = 0; k < observations.size(); ++k) {
    const int i = observations[k].second;
    couple(obs_lm[k], t_of(i));
    couple(obs_lm[k], r_of(i));
    couple(t_of(i), r_of(i));
  }
  PairSystem sys(unknowns, pairs);
  const Eigen::Matrix2d id = Eigen::Matrix2d::Identity();
  auto t_known = [&](int i) { return Eigen::Vector2d(poses[i]->estimate().translation()); };
  auto r_known = [&](int i) { return unitVector(poses[i]->estimate().angle()); };
  for (std::size_t k = 0; k < relative.size(); ++k) {
    const EdgeSE2* e = relative[k];
    const auto [u, v] = ends[k];
    const double scale = p.relative_weight[k];
    const double wt = scale * 0.5 * e->information().topLeftCorner<2, 2>().trace();
    addResidual<3>(sys,
                   {{{t_of(v), id, t_known(v)},
                     {t_of(u), -id, t_known(u)},
                     {r_of(u), -vecMatrix(e->measurement().translation()), r_known(u)}}},
                   wt);
    addResidual<2>(
        sys,
        {{{r_of(v), id, r_known(v)}, {r_of(u), -rotation2(e->measurement().angle()), r_known(u)}}},
        scale * e->information()(2, 2));
  }
  for (std::size_t k = 0; k < observations.size(); ++k) {
    const auto [obs, i] = observations[k];
    const double wl = p.observation_weight[k] * 0.5 * obs->information().trace();
    const Eigen::Vector2d xl = static_cast<const VertexXY*>(obs->vertex(1))->estimate();
    addResidual<3>(sys,
                   {{{obs_lm[k], id, xl},
                     {t_of(i), -id, t_known(i)},
                     {r_of(i), -vecMatrix(obs->measurement()), r_known(i)}}},
                   wl);
  }
  for (const auto& [prior, i] : priors) {
    const SE2& z = prior->measurement();
    addResidual<2>(sys, {{{t_of(i), id, t_known(i)}, {-1, id, -z.translation()}}},
                   0.5 * prior->information().topLeftCorner<2, 2>().trace());
    addResidual<2>(sys, {{{r_of(i), id, r_known(i)}, {-1, id, -unitVector(z.angle())}}},
                   prior->information()(2, 2));
  }
  Eigen::VectorXd x;
  if (!spd.solve(sys, x)) return false;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const int r = r_of(static_cast<int>(i));
    if (r >= 0) theta[i] = std::atan2(x[2 * r + 1], x[2 * r]);
  }
  return true;
}

/// Index of each pose by its id, through a table over the graph's id range when the ids are
/// dense enough (one array access per look-up), else through a hash map.
class PoseIndex {
 public:
  PoseIndex(const Graph& graph, std::size_t expected) {
    const auto& vertices = graph.vertices();
    min_id_ = vertices.empty() ? 0 : vertices.begin()->first;
    const long long max_id = vertices.empty() ? -1 : vertices.rbegin()->first;
    dense_ = max_id - min_id_ < 4 * static_cast<long long>(vertices.size()) + 16;
    table_.assign(dense_ ? static_cast<std::size_t>(max_id - min_id_ + 1) : 0u, -1);
    if (!dense_) hashed_.reserve(expected);
  }
  int& slot(VertexId id) {
    return dense_ ? table_[static_cast<std::size_t>(id - min_id_)] : hashed_[id];
  }
  /// The slot's value, -1 when the id has none (without adding it to the hash map).
  [[nodiscard]] int lookup(VertexId id) const {
    if (dense_) return table_[static_cast<std::size_t>(id - min_id_)];
    const auto it = hashed_.find(id);
    return it == hashed_.end() ? -1 : it->second;
  }

 private:
  long long min_id_ = 0;
  bool dense_ = true;
  std::vector<int> table_;
  std::unordered_map<VertexId, int> hashed_;
};

/// The Problem of `graph` over the edges of positive `weight` (all, of weight 1, when it
/// is empty); its poses are empty when no such EDGE_SE2 reaches any.
Problem collectProblem(const Graph& graph, const EdgeWeight& weight) {
  Problem p;
  std::vector<const EdgePriorSE2*> all_priors;
  std::vector<std::pair<const EdgeSE2XY*, double>> all_observations;
  for (const auto& e : graph.edges()) {
    const double w = weight ? weight(*e) : 1.0;
    if (!(w > 0.0)) continue;
    if (const auto* se2 = dynamic_cast<const EdgeSE2*>(e.get())) {
      p.relative.push_back(se2);
      p.relative_weight.push_back(w);
    } else if (const auto* prior = dynamic_cast<const EdgePriorSE2*>(e.get())) {
      all_priors.push_back(prior);
    } else if (const auto* obs = dynamic_cast<const EdgeSE2XY*>(e.get())) {
      all_observations.emplace_back(obs, w);
    }
  }
  PoseIndex index(graph, 2 * p.relative.size());
  for (const EdgeSE2* se2 : p.relative) {
    for (std::size_t k = 0; k < 2; ++k) index.slot(se2->vertex(k)->id()) = 0;  // marked
  }
  for (const auto& [id, v] : graph.vertices()) {
    if (index.lookup(id) < 0) continue;
    index.slot(id) = static_cast<int>(p.poses.size());
    p.poses.push_back(static_cast<VertexSE2*>(v.get()));
  }
  // Index of a pose vertex (-1: not a pose reached by an EDGE_SE2).
  auto pose_index = [&](const Vertex* v) { return index.lookup(v->id()); };
  p.ends.resize(p.relative.size());
  for (std::size_t k = 0; k < p.relative.size(); ++k) {
    p.ends[k] = {pose_index(p.relative[k]->vertex(0)), pose_index(p.relative[k]->vertex(1))};
  }
  p.anchored.assign(p.poses.size(), 0);
  for (std::size_t i = 0; i < p.poses.size(); ++i) p.anchored[i] = p.poses[i]->fixed() ? 1 : 0;
  for (const EdgePriorSE2* prior : all_priors) {
    const int i = pose_index(prior->vertex(0));
    if (i < 0) continue;
    p.anchored[static_cast<std::size_t>(i)] = 1;
    p.priors.emplace_back(prior, i);
  }
  for (const auto& [obs, w] : all_observations) {
    const int i = pose_index(obs->vertex(0));
    if (i < 0) continue;
    p.observations.emplace_back(obs, i);
    p.observation_weight.push_back(w);
  }
  return p;
}

/// The gauge poses: connected groups (over EDGE_SE2) are flooded from anchored poses
/// first, then in id order (poses are numbered by id); a group reached from an unanchored
/// pose has no anchor and holds that pose, its lowest id, where it is.
std::vector<char> gaugePoses(const Problem& p) {
  const int n = p.size();
  // Neighbours of every pose over EDGE_SE2 (CSR).
  std::vector<int> adj_ptr(static_cast<std::size_t>(n) + 1, 0), adj;
  for (const auto& [i, j] : p.ends) {
    ++adj_ptr[i + 1];
    ++adj_ptr[j + 1];
  }
  for (int i = 0; i < n; ++i) adj_ptr[i + 1] += adj_ptr[i];
  adj.resize(static_cast<std::size_t>(adj_ptr[n]));
  {
    std::vector<int> next(adj_ptr.begin(), adj_ptr.end() - 1);
    for (const auto& [i, j] : p.ends) {
      adj[next[i]++] = j;
      adj[next[j]++] = i;
    }
  }
  std::vector<char> gauge(static_cast<std::size_t>(n), 0);
  std::vector<int> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  std::stable_partition(order.begin(), order.end(), [&](int i) { return p.anchored[i] != 0; });
  std::vector<char> reached(static_cast<std::size_t>(n), 0);
  std::vector<int> queue;
  queue.reserve(static_cast<std::size_t>(n));
  for (int s : order) {
    if (reached[s]) continue;
    if (!p.anchored[s]) gauge[s] = 1;
    queue.clear();
    queue.push_back(s);
    reached[s] = 1;
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const int u = queue[head];
      for (int k = adj_ptr[u]; k < adj_ptr[u + 1]; ++k) {
        if (!reached[adj[k]]) {
          reached[adj[k]] = 1;
          queue.push_back(adj[k]);
        }
      }
    }
  }
  return gauge;
}

/// The free landmarks in the order of their first observation; obs_landmark[k] is the
/// index of observation k's landmark, -1 when it is fixed (both systems number them so).
std::vector<VertexXY*> freeLandmarks(Graph& graph, const Problem& p,
                                     std::vector<int>& obs_landmark) {
  std::unordered_map<const Vertex*, int> landmark_index;
  std::vector<VertexXY*> landmarks;
  obs_landmark.assign(p.observations.size(), -1);
  for (std::size_t k = 0; k < p.observations.size(); ++k) {
    const Vertex* l = p.observations[k].first->vertex(1);
    if (l->fixed()) continue;
    auto [it, inserted] = landmark_index.emplace(l, static_cast<int>(landmarks.size()));
    if (inserted) landmarks.push_back(static_cast<VertexXY*>(graph.vertex(l->id())));
    obs_landmark[k] = it->second;
  }
  return landmarks;
}

/// Step 1 of initializeGlobal without landmark observations: the relaxed rotations of
/// the free poses (var >= 0) from the relative-pose edges and priors alone, in `sys` (the
/// pattern of the pose pairs, zero). Updates theta; false when the system is singular.
bool odometryOrientations(const Problem& p, const std::vector<int>& var, PairSystem& sys,
                          std::vector<double>& theta, SpdSolver& spd) {
  Eigen::VectorXd& rhs = sys.rhs();
  for (std::size_t k = 0; k < p.relative.size(); ++k) {
    const EdgeSE2* edge = p.relative[k];
    const auto [u, v] = p.ends[k];
    const double w = p.relative_weight[k] * edge->information()(2, 2);
    const Eigen::Matrix2d q = rotation2(edge->measurement().angle());
    const int a = var[u], b = var[v];
    // w |r_v - q r_u|^2: blocks (u,u) = (v,v) = w I, (u,v) = -w q^T, (v,u) = -w q.
    if (a >= 0) sys.add(a, a, w * Eigen::Matrix2d::Identity());
    if (b >= 0) sys.add(b, b, w * Eigen::Matrix2d::Identity());
    if (a >= 0 && b >= 0) {
      sys.add(a, b, -w * q.transpose());
    } else if (a >= 0) {
      rhs.segment<2>(2 * a) += w * q.transpose() * unitVector(theta[v]);
    } else if (b >= 0) {
      rhs.segment<2>(2 * b) += w * q * unitVector(theta[u]);
    }
  }
  for (const auto& [prior, i] : p.priors) {
    if (var[i] < 0) continue;
    const double w = prior->information()(2, 2);
    sys.add(var[i], var[i], w * Eigen::Matrix2d::Identity());
    rhs.segment<2>(2 * var[i]) += w * unitVector(prior->measurement().angle());
  }
  Eigen::VectorXd r;
  if (!spd.solve(sys, r)) return false;
  for (int i = 0; i < p.size(); ++i) {
    if (var[i] >= 0) theta[i] = std::atan2(r[2 * var[i] + 1], r[2 * var[i]]);
  }
  return true;
}

/// Adds the residual (x_b - x_a) - d with 2x2 weight W to `sys`; -1 marks a known position.
void addDifference(PairSystem& sys, int a, const Eigen::Vector2d& xa, int b,
                   const Eigen::Vector2d& xb, const Eigen::Vector2d& d, const Eigen::Matrix2d& w) {
  Eigen::VectorXd& rhs = sys.rhs();
  if (a >= 0) sys.add(a, a, w);
  if (b >= 0) sys.add(b, b, w);
  if (a >= 0 && b >= 0) sys.add(a, b, -w);
  if (a >= 0)
    rhs.segment<2>(2 * a) += -w * d + (b < 0 ? Eigen::Vector2d(w * xb) : Eigen::Vector2d::Zero());
  if (b >= 0)
    rhs.segment<2>(2 * b) += w * d + (a < 0 ? Eigen::Vector2d(w * xa) : Eigen::Vector2d::Zero());
}

/// Step 2 of initializeGlobal: translations of the free poses (var >= 0) and positions of
/// the free landmarks (unknown nv + their index), orientations held at theta. `pairs`
/// holds the pose pairs; the pose-landmark pairs are added here. Without landmarks the
/// system is laid out in `pose_system` when it is given (the orientations' system, of the
/// same pattern: laid out once). Sets the estimates and counts them in `report`; false
/// when the system is singular.
bool solvePositions(const Problem& p, const std::vector<int>& var, int nv,
                    const std::vector<VertexXY*>& landmarks, const std::vector<int>& obs_landmark,
                    std::vector<std::pair<int, int>> pairs, const std::vector<double>& theta,
                    PairSystem* pose_system, SpdSolver& spd, InitializationReport& report) {
  std::vector<int> obs_var(p.observations.size(), -1);  // the landmark's unknown, -1: fixed
  for (std::size_t k = 0; k < p.observations.size(); ++k) {
    if (obs_landmark[k] < 0) continue;
    obs_var[k] = nv + obs_landmark[k];
    const int a = var[p.observations[k].second];
    if (a >= 0) pairs.emplace_back(a, obs_var[k]);
  }
  const int nt = nv + static_cast<int>(landmarks.size());
  if (nt == 0) return true;
  std::optional<PairSystem> own;
  if (pose_system && landmarks.empty()) {
    pose_system->clear();
  } else {
    own.emplace(nt, pairs);
  }
  PairSystem& sys = own ? *own : *pose_system;
  auto pos = [&](int i) { return p.poses[i]->estimate().translation(); };
  for (std::size_t k = 0; k < p.relative.size(); ++k) {
    const EdgeSE2* edge = p.relative[k];
    const auto [u, v] = p.ends[k];
    const Eigen::Matrix2d r = rotation2(theta[u]) * edge->measurement().rotation();
    const Eigen::Matrix2d w =
        p.relative_weight[k] * r * edge->information().topLeftCorner<2, 2>() * r.transpose();
    addDifference(sys, var[u], pos(u), var[v], pos(v),
                  rotation2(theta[u]) * edge->measurement().translation(), w);
  }
  for (std::size_t k = 0; k < p.observations.size(); ++k) {
    const auto [obs, i] = p.observations[k];
    const Eigen::Vector2d xl = static_cast<const VertexXY*>(obs->vertex(1))->estimate();
    const Eigen::Matrix2d r = rotation2(theta[i]);
    const Eigen::Matrix2d w = p.observation_weight[k] * r * obs->information() * r.transpose();
    addDifference(sys, var[i], pos(i), obs_var[k], xl, r * obs->measurement(), w);
  }
  for (const auto& [prior, i] : p.priors) {
    if (var[i] < 0) continue;
    const Eigen::Matrix2d r = prior->measurement().rotation();
    const Eigen::Matrix2d w = r * prior->information().topLeftCorner<2, 2>() * r.transpose();
    addDifference(sys, -1, Eigen::Vector2d::Zero(), var[i], Eigen::Vector2d::Zero(),
                  prior->measurement().translation(), w);
  }
  Eigen::VectorXd x;
  if (!spd.solve(sys, x)) return false;
  for (int i = 0; i < p.size(); ++i) {
    if (var[i] < 0) continue;
    p.poses[i]->setEstimate(SE2(x.segment<2>(2 * var[i]), theta[i]));
    ++report.poses;
  }
  for (std::size_t k = 0; k < landmarks.size(); ++k) {
    landmarks[k]->setEstimate(x.segment<2>(2 * (nv + static_cast<int>(k))));
    ++report.landmarks;
  }
  return true;
}

/// `report` for a system that was not solved: which, and the linear solver's reason.
InitializationReport failed(InitializationReport& report, const char* system,
                            const SpdSolver& spd) {
  report.failed = true;
  report.message =
      std::string(system) + " not solved (" + spd.failure() + "): initial estimates kept";
  report.analysis_seconds = spd.analysisSeconds();
  return report;
}

}  // namespace

InitializationReport initializeGlobal(Graph& graph) { return initializeGlobal(graph, nullptr); }

InitializationReport initializeGlobal(Graph& graph, LinearSolver* solver) {
  return initializeGlobal(graph, solver, EdgeFilter{});
}

InitializationReport initializeGlobal(Graph& graph, LinearSolver* solver,
                                      const EdgeFilter& use_edge) {
  if (!use_edge) return initializeGlobalWeighted(graph, solver, EdgeWeight{});
  return initializeGlobalWeighted(graph, solver,
                                  [&use_edge](const Edge& e) { return use_edge(e) ? 1.0 : 0.0; });
}

InitializationReport initializeGlobalWeighted(Graph& graph, LinearSolver* solver,
                                              const EdgeWeight& weight) {
  const auto t0 = std::chrono::steady_clock::now();
  InitializationReport report;
  SpdSolver spd(solver);
  const Problem p = collectProblem(graph, weight);
  const int n = p.size();
  if (n == 0) {
    report.message = "no EDGE_SE2 in the graph: nothing to initialise";
    return report;
  }
  const std::vector<char> gauge = gaugePoses(p);

  // Step 1: orientations by chordal relaxation. Each pose's rotation is the unit vector
  // r_i = (cos theta_i, sin theta_i), relaxed to any vector of R^2; an edge asks for
  // r_j = R(dtheta_ij) r_i and a prior for r_i = r(z), weighted by the angular
  // information. The linear least-squares solution, normalised, gives the angles; no 2*pi
  // ambiguity arises. Unknowns: every pose that is neither fixed nor a gauge.
  // With landmark observations, translations and landmarks are unknowns of the same
  // system (jointOrientations): then R_i d = D r_i with D = [d_x -d_y; d_y d_x], so an
  // odometry edge asks t_j - t_i - D r_i = 0 besides r_j = R(dtheta) r_i, and an
  // observation z of landmark l asks l - t_i - Z r_i = 0: all linear. The landmarks, which
  // the robot sees from poses far apart along its path, then correct the orientations that
  // odometry alone lets drift. Only the normalised r_i are kept: step 2 places poses and
  // landmarks again with them.
  std::vector<int> obs_landmark;
  const std::vector<VertexXY*> landmarks = freeLandmarks(graph, p, obs_landmark);
  std::vector<int> var(static_cast<std::size_t>(n), -1);
  int nv = 0;
  for (int i = 0; i < n; ++i) {
    if (!p.poses[i]->fixed() && !gauge[i]) var[i] = nv++;
  }
  std::vector<double> theta(static_cast<std::size_t>(n), 0.0);
  for (int i = 0; i < n; ++i) theta[i] = p.poses[i]->estimate().angle();
  // Pairs of unknowns coupled by an edge: the pattern of both systems (the positions'
  // adds the landmarks).
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(p.relative.size() + p.observations.size());
  for (const auto& [i, j] : p.ends) {
    if (var[i] >= 0 && var[j] >= 0) pairs.emplace_back(var[i], var[j]);
  }
  if (nv > 0 && !p.observations.empty()) {
    if (!jointOrientations(p, obs_landmark, static_cast<int>(landmarks.size()), var, nv, theta,
                           spd)) {
      return failed(report, "orientation system (with landmarks)", spd);
    }
  }
  // Without landmark observations both steps solve a system of the pose pairs' pattern.
  std::optional<PairSystem> pose_system;
  if (nv > 0 && p.observations.empty()) {
    pose_system.emplace(nv, pairs);
    if (!odometryOrientations(p, var, *pose_system, theta, spd)) {
      return failed(report, "orientation system", spd);
    }
  }

  // Step 2: translations of poses and positions of landmarks, orientations held.
  if (!solvePositions(p, var, nv, landmarks, obs_landmark, std::move(pairs), theta,
                      pose_system ? &*pose_system : nullptr, spd, report)) {
    return failed(report, "position system", spd);
  }
  report.analysis_seconds = spd.analysisSeconds();
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return report;
}

}  // namespace graphslam::init
