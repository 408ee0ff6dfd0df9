// SPDX-License-Identifier: MIT
// replayGraph: the replay protocol of replay.h (plan, initial estimates, timed updates).
#include "graphslam/incremental/replay.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>
#include <limits>
#include <map>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

#include "graphslam/core/graph_copy.h"
#include "graphslam/support/error.h"

namespace graphslam::incremental {

namespace {

/// Which vertices are poses, and at which step each edge and landmark comes.
struct Plan {
  std::string pose_tag;
  std::vector<const Vertex*> poses;  ///< in id order: step k adds poses[k]
  std::unordered_set<VertexId> is_pose;
  /// Per step: the edges whose largest pose endpoint is that step's pose, in file order,
  /// then the edges without a pose endpoint that the step completes.
  std::vector<std::vector<const Edge*>> edges;
  /// Per step: the first edge joining exactly the previous pose and this one, or null.
  std::vector<const Edge*> odometry;
  /// Landmarks without an edge to a pose: added at the first step, with the file's estimate.
  std::vector<const Vertex*> unreached;
  std::size_t num_landmarks = 0;
};

/// The tag of the vertices of the largest dimension (the most common one when several
/// tags have it; the first by name on a tie).
std::string poseTag(const Graph& graph, const TypeRegistry& types) {
  int dimension = 0;
  std::map<std::string, std::size_t> counts;
  for (const auto& [id, v] : graph.vertices()) {
    const std::string* tag = types.tagOf(*v);
    if (!tag) throw Error("vertex " + std::to_string(id) + ": its type is not registered");
    if (v->dimension() > dimension) counts.clear();
    dimension = std::max(dimension, v->dimension());
    if (v->dimension() == dimension) ++counts[*tag];
  }
  std::string best;
  std::size_t most = 0;
  for (const auto& [tag, n] : counts) {
    if (n > most) best = tag, most = n;
  }
  return best;
}

/// The step of every landmark (its first edge to a pose) and of every edge.
Plan makePlan(const Graph& source, const TypeRegistry& types) {
  Plan plan;
  plan.pose_tag = poseTag(source, types);
  std::unordered_map<VertexId, int> pose_index;
  for (const auto& [id, v] : source.vertices()) {
    if (*types.tagOf(*v) != plan.pose_tag) continue;
    pose_index.emplace(id, static_cast<int>(plan.poses.size()));
    plan.is_pose.insert(id);
    plan.poses.push_back(v.get());
  }
  const std::size_t n = plan.poses.size();
  plan.edges.resize(n);
  plan.odometry.assign(n, nullptr);
  std::unordered_map<VertexId, int> landmark_step;
  std::vector<const Edge*> without_pose;
  for (const auto& e : source.edges()) {
    if (!e->active()) continue;
    int step = -1, low = -1;
    for (VertexId id : e->vertexIds()) {
      const auto it = pose_index.find(id);
      if (it == pose_index.end()) continue;
      low = low < 0 ? it->second : std::min(low, it->second);
      step = std::max(step, it->second);
    }
    if (step < 0) {
      without_pose.push_back(e.get());
      continue;
    }
    plan.edges[static_cast<std::size_t>(step)].push_back(e.get());
    const std::size_t k = static_cast<std::size_t>(step);
    if (e->numVertices() == 2 && low == step - 1 && !plan.odometry[k]) plan.odometry[k] = e.get();
    for (VertexId id : e->vertexIds()) {
      if (pose_index.count(id)) continue;
      auto [it, fresh] = landmark_step.emplace(id, step);
      if (!fresh) it->second = std::min(it->second, step);
    }
  }
  for (const auto& [id, v] : source.vertices()) {
    if (pose_index.count(id)) continue;
    ++plan.num_landmarks;
    if (!landmark_step.count(id)) plan.unreached.push_back(v.get());
  }
  if (n == 0) return plan;
  for (const Edge* e : without_pose) {
    int step = 0;
    for (VertexId id : e->vertexIds()) {
      const auto it = landmark_step.find(id);
      if (it != landmark_step.end()) step = std::max(step, it->second);
    }
    plan.edges[static_cast<std::size_t>(step)].push_back(e);
  }
  return plan;
}

/// e, J of `slot` and Omega of an edge in a graph, at the current estimates.
struct Linearization {
  Eigen::VectorXd error;
  Eigen::MatrixXd jacobian;
  Eigen::MatrixXd information;
};

Linearization linearize(Edge& edge, std::size_t slot, int dimension) {
  const int d = edge.dimension();
  // Jacobians first: a numeric one perturbs in place and leaves the stored error stale.
  edge.linearizeOplus();
  edge.computeError();
  return {Eigen::Map<const Eigen::VectorXd>(edge.errorData(), d),
          Eigen::Map<const Eigen::MatrixXd>(edge.jacobianData(slot), d, dimension),
          Eigen::Map<const Eigen::MatrixXd>(edge.informationData(), d, d)};
}

/// Gauss-Newton on the one edge's e^T Omega e over the vertex in `slot`, from its current
/// estimate. False when J^T Omega J is rank deficient or anything is not finite.
bool gaussNewton(Edge& edge, std::size_t slot, Vertex& v, const ReplayOptions& options) {
  for (int it = 0; it < options.init_max_iterations; ++it) {
    const Linearization l = linearize(edge, slot, v.dimension());
    if (!l.error.allFinite() || !l.jacobian.allFinite()) return false;
    const Eigen::MatrixXd h = l.jacobian.transpose() * l.information * l.jacobian;
    const Eigen::VectorXd g = l.jacobian.transpose() * l.information * l.error;
    const Eigen::VectorXd eig = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(h).eigenvalues();
    if (!(eig.minCoeff() > options.init_rank_tolerance * eig.maxCoeff())) return false;
    const Eigen::VectorXd step = -h.ldlt().solve(g);
    if (!step.allFinite()) return false;
    v.oplus(step.data());
    if (step.norm() < options.init_step_tolerance) break;
  }
  std::vector<double> data(static_cast<std::size_t>(v.estimateDataDimension()));
  v.getEstimateData(data.data());
  return std::all_of(data.begin(), data.end(), [](double x) { return std::isfinite(x); });
}

void copyEstimate(const Vertex& from, Vertex& to) {
  std::vector<double> data(static_cast<std::size_t>(from.estimateDataDimension()));
  from.getEstimateData(data.data());
  to.setEstimateData(data.data());
}

/// Replays one graph (replayGraph).
class Replayer {
 public:
  Replayer(const Graph& source, const TypeRegistry& types, Graph& target,
           const ReplayOptions& options)
      : source_(source),
        types_(types),
        options_(options),
        plan_(makePlan(source, types)),
        optimizer_(target, options.optimizer) {
    for (const auto& [id, p] : source.parameters()) {
      if (options.resume_path.empty()) target.addParameter(copyParameter(*p, types));
      scratch_.addParameter(copyParameter(*p, types));
    }
    if (!options.resume_path.empty()) resume();
  }

  ReplayResult run() {
    result_.pose_tag = plan_.pose_tag;
    result_.num_landmarks = plan_.num_landmarks;
    for (std::size_t k = result_.first_step; k < plan_.poses.size(); ++k) {
      if (!runStep(k)) break;
      if (options_.checkpoint_every > 0 && (k + 1) % options_.checkpoint_every == 0) {
        checkpoint(k + 1);
      }
    }
    result_.final_chi2 = optimizer_.chi2();
    result_.marginalized = optimizer_.marginalizedCount();
    result_.window_vertices = optimizer_.graph().numVertices();
    if (result_.ok && !plan_.poses.empty() && options_.refine_threshold > 0.0) refine();
    return std::move(result_);
  }

 private:
  /// Adds step k's pose, landmarks and edges, updates (timed); false when update() failed.
  bool runStep(std::size_t k) {
    ReplayStep step;
    const Vertex& pose = *plan_.poses[k];
    step.pose = pose.id();
    addPose(k);
    if (options_.optimizer.window.enabled()) {
      double stamp = std::numeric_limits<double>::quiet_NaN();
      if (pose.parameterDataDimension() > 0) {
        std::vector<double> data(static_cast<std::size_t>(pose.parameterDataDimension()));
        pose.getParameterData(data.data());
        stamp = data[0];
      }
      optimizer_.addState(pose.id(), stamp);
    }
    if (k == 0) {
      for (const Vertex* v : plan_.unreached) {
        optimizer_.addVertex(copyVertex(*v, types_));
        ++step.new_landmarks;
        if (!v->fixed()) ++result_.initialised_from_file;
      }
    }
    for (const Edge* e : plan_.edges[k]) {
      if (refused(*e)) continue;
      step.new_landmarks += addLandmarksOf(*e);
      optimizer_.addEdge(copyEdge(*e, types_));
      ++step.new_edges;
    }
    const auto start = std::chrono::steady_clock::now();
    const bool ok = optimizer_.update();
    step.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    step.stats = optimizer_.lastStats();
    result_.total_seconds += step.seconds;
    if (!ok) {
      const UpdateFailure& f = optimizer_.failure();
      result_.ok = false;
      result_.error =
          "step " + std::to_string(k) + " (pose " + std::to_string(step.pose) + "): " +
          (f.message.empty() ? "update failed at vertex " + std::to_string(f.vertex) : f.message);
      result_.steps.push_back(step);
      return false;
    }
    if (options_.record_chi2) step.chi2 = optimizer_.chi2();
    result_.steps.push_back(step);
    if (options_.after_step) options_.after_step(k, result_.steps.back(), optimizer_.graph());
    return true;
  }

  /// Whether `edge` reaches a marginalised vertex: then the optimizer refuses it and the
  /// refusal is counted.
  bool refused(const Edge& edge) {
    const auto ids = edge.vertexIds();
    const bool again = options_.optimizer.window.reinitialize_landmarks;
    if (std::none_of(ids.begin(), ids.end(), [&](VertexId id) {
          // A landmark seen again is added anew (addLandmarksOf) when the window allows.
          return optimizer_.isMarginalized(id) && !(again && !plan_.is_pose.count(id));
        })) {
      return false;
    }
    try {
      optimizer_.addEdge(copyEdge(edge, types_));
    } catch (const InputError& refusal) {
      if (result_.refused_edges++ == 0) result_.first_refusal = refusal.what();
      return true;
    }
    throw Error("replay: an edge to a marginalised vertex was not refused");
  }

  /// The optimizer's state and the replay's position (the next step) to the checkpoint.
  void checkpoint(std::size_t next) {
    std::string note = std::to_string(next) + ' ' + std::to_string(result_.gaps) + ' ' +
                       std::to_string(result_.initialised_from_file) + ' ' +
                       std::to_string(result_.refused_edges) + '\n' + result_.first_refusal + '\n';
    if (options_.checkpoint_note) note += options_.checkpoint_note();
    optimizer_.saveCheckpoint(options_.checkpoint_path, types_, note);
  }

  /// Loads the checkpoint to resume from and the replay's position in it.
  void resume() {
    const std::string note = optimizer_.loadCheckpoint(options_.resume_path, types_);
    std::istringstream in(note);
    std::size_t next = 0;
    in >> next >> result_.gaps >> result_.initialised_from_file >> result_.refused_edges;
    in.ignore(1);
    std::getline(in, result_.first_refusal);
    if (!in || next > plan_.poses.size()) {
      throw InputError(options_.resume_path +
                       ": checkpoint refused: it was not written by a replay of this input "
                       "(its position is step " +
                       std::to_string(next) + " of " + std::to_string(plan_.poses.size()) + ")");
    }
    result_.first_step = next;
    std::string rest((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (options_.on_resume) options_.on_resume(rest);
  }

  /// IncrementalOptimizer::refine() after the last step, timed apart.
  void refine() {
    const auto start = std::chrono::steady_clock::now();
    const bool ok = optimizer_.refine(options_.refine_threshold);
    result_.refine_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    result_.refine_stats = optimizer_.lastStats();
    if (!ok) {
      result_.ok = false;
      result_.error = "the final refine(): " + optimizer_.failure().message;
      return;
    }
    result_.refined_chi2 = optimizer_.chi2();
  }

  /// Pose k, composed from pose k-1 and the odometry edge; the file's estimate for the
  /// first pose, a fixed one, a gap or an odometry edge that does not determine it.
  void addPose(std::size_t k) {
    const Vertex& pose = *plan_.poses[k];
    auto vertex = copyVertex(pose, types_);
    const Edge* odometry = plan_.odometry[k];
    if (k > 0 && !pose.fixed()) {
      if (!odometry) {
        ++result_.gaps;
      } else if (!place(*vertex, *odometry)) {
        ++result_.initialised_from_file;
      }
    }
    optimizer_.addVertex(std::move(vertex));
  }

  /// Adds the landmarks of `edge` that the graph does not hold yet, each placed by the
  /// edge; returns how many.
  int addLandmarksOf(const Edge& edge) {
    int added = 0;
    for (VertexId id : edge.vertexIds()) {
      if (optimizer_.graph().hasVertex(id)) continue;
      const Vertex& landmark = *source_.vertex(id);
      auto vertex = copyVertex(landmark, types_);
      if (!landmark.fixed() && !place(*vertex, edge)) ++result_.initialised_from_file;
      optimizer_.addVertex(std::move(vertex));
      ++added;
    }
    return added;
  }

  /// Sets `fresh` (not yet in the graph) where `edge` alone puts it, the edge's other
  /// vertices at their current estimates (the file's, for another new landmark of the same
  /// edge). False, with `fresh` unchanged, when the edge does not determine it.
  bool place(Vertex& fresh, const Edge& edge) {
    const Graph& current = optimizer_.graph();
    const std::string& tag = *types_.tagOf(fresh);
    std::size_t slot = 0;
    const Vertex* start = nullptr;  // a vertex of the same type in the edge
    for (std::size_t s = 0; s < edge.numVertices(); ++s) {
      const VertexId id = edge.vertexId(s);
      if (id == fresh.id()) {
        slot = s;
        continue;
      }
      const Vertex* v = current.hasVertex(id) ? current.vertex(id) : source_.vertex(id);
      if (!start && current.hasVertex(id) && *types_.tagOf(*v) == tag) start = v;
      scratch_.addVertex(copyVertex(*v, types_));
    }
    auto copy = copyVertex(fresh, types_);  // its parameter data (a time stamp) may matter
    copyEstimate(start ? *start : *types_.createVertex(tag), *copy);
    copy->setFixed(false);
    Vertex& v = scratch_.addVertex(std::move(copy));
    Edge& e = scratch_.addEdge(copyEdge(edge, types_));
    const bool solved = solve(e, slot, v);
    if (solved) copyEstimate(v, fresh);
    for (VertexId id : edge.vertexIds()) scratch_.removeVertex(id);
    return solved;
  }

  /// Gauss-Newton for the vertex in `slot` of `edge`, once more from an offset start when
  /// the first run fails.
  bool solve(Edge& edge, std::size_t slot, Vertex& v) const {
    v.push();
    if (gaussNewton(edge, slot, v, options_)) return true;
    v.pop();
    const std::vector<double> offset(static_cast<std::size_t>(v.dimension()),
                                     options_.init_restart_offset);
    v.oplus(offset.data());
    return gaussNewton(edge, slot, v, options_);
  }

  const Graph& source_;
  const TypeRegistry& types_;
  const ReplayOptions& options_;
  Plan plan_;
  IncrementalOptimizer optimizer_;
  /// Holds one edge and copies of its vertices while a vertex is placed from it.
  Graph scratch_;
  ReplayResult result_;
};

}  // namespace

ReplayResult replayGraph(const Graph& source, const TypeRegistry& types, Graph& target,
                         const ReplayOptions& options) {
  if (target.numVertices() != 0 || target.numEdges() != 0 || !target.parameters().empty()) {
    throw Error("replayGraph: the target graph must be empty");
  }
  Replayer replayer(source, types, target, options);
  return replayer.run();
}

}  // namespace graphslam::incremental
