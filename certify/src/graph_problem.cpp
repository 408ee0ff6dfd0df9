// SPDX-License-Identifier: MIT
// A pose graph as SE-Sync's problem, and refusals of what it cannot express.
#include <cmath>
#include <map>
#include <string>

#include "graphslam/certify/problem.h"
#include "graphslam/diagnostics/information.h"
#include "graphslam/support/error.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam3d/edges.h"
#include "graphslam/types_slam3d/vertex_se3.h"
#include "problem_impl.h"

namespace graphslam::certify {

namespace {

/// 2 or 3 for a pose vertex, 0 for anything else.
int poseDimension(const Vertex& v) {
  if (dynamic_cast<const types_slam2d::VertexSE2*>(&v)) return 2;
  if (dynamic_cast<const types_slam3d::VertexSE3*>(&v)) return 3;
  return 0;
}

/// The graph's pose dimension; throws for non-pose vertices, mixed dimensions, several
/// fixed vertices.
int checkVertices(const Graph& graph) {
  int d = 0;
  VertexId first = 0, fixed = 0;
  int num_fixed = 0;
  for (const auto& [id, v] : graph.vertices()) {
    const int dim = poseDimension(*v);
    if (dim == 0) {
      throw InputError("certify supports pose graphs only: vertex " + std::to_string(id) +
                       " is a " + typeName(typeid(*v)) +
                       ", not a VERTEX_SE2 or VERTEX_SE3:QUAT pose (landmarks and other "
                       "vertices have no place in SE-Sync's relaxation)");
    }
    if (d != 0 && dim != d) {
      throw InputError("certify: vertex " + std::to_string(first) + " is a " + std::to_string(d) +
                       "D pose and vertex " + std::to_string(id) + " a " + std::to_string(dim) +
                       "D one; 2D and 3D poses together are not supported");
    }
    if (d == 0) first = id;
    d = dim;
    if (v->fixed()) {
      if (++num_fixed > 1) {
        throw InputError("certify: vertices " + std::to_string(fixed) + " and " +
                         std::to_string(id) +
                         " are both fixed; SE-Sync's problem has no fixed poses (at most one "
                         "fixed vertex is accepted: it only chooses the frame)");
      }
      fixed = id;
    }
  }
  if (d == 0) throw InputError("certify: the graph has no poses");
  return d;
}

std::string edgeName(const Edge& e) {
  if (e.vertexIds().size() == 1) return "the edge on vertex " + std::to_string(e.vertexId(0));
  std::string s = "the edge between vertices";
  for (VertexId id : e.vertexIds()) s += " " + std::to_string(id);
  return s;
}

/// The measurement of a relative-pose edge with SE-Sync's weights; throws for other edges
/// and for information without positive weights.
Measurement measurementOf(const Edge& e, int d, const std::map<VertexId, int>& index) {
  Measurement m;
  if (const auto* se2 = dynamic_cast<const types_slam2d::EdgeSE2*>(&e); se2 && d == 2) {
    m.rotation = se2->measurement().rotation();
    m.translation = se2->measurement().translation();
    m.tau = inverseTraceWeight(se2->information().topLeftCorner<2, 2>());
    m.kappa = se2->information()(2, 2);
  } else if (const auto* se3 = dynamic_cast<const types_slam3d::EdgeSE3*>(&e); se3 && d == 3) {
    m.rotation = se3->measurement().rotation();
    m.translation = se3->measurement().translation();
    m.tau = inverseTraceWeight(se3->information().topLeftCorner<3, 3>());
    m.kappa = inverseTraceWeight(se3->information().bottomRightCorner<3, 3>()) / 2.0;
  } else {
    throw InputError("certify supports pose graphs only: " + edgeName(e) + " is a " +
                     typeName(typeid(e)) + ", not an " + (d == 2 ? "EDGE_SE2" : "EDGE_SE3:QUAT") +
                     " relative-pose measurement (priors and landmark observations are not "
                     "part of SE-Sync's problem)");
  }
  if (!(std::isfinite(m.kappa) && m.kappa > 0.0)) {
    throw InputError("certify: " + edgeName(e) +
                     " has no usable rotation information (its rotation block gives no "
                     "positive weight); SE-Sync's relaxation needs every rotation measured");
  }
  if (!(std::isfinite(m.tau) && m.tau > 0.0)) {
    throw InputError("certify: " + edgeName(e) +
                     " has no usable translation information (its translation block gives no "
                     "positive weight)");
  }
  m.i = index.at(e.vertexId(0));
  m.j = index.at(e.vertexId(1));
  return m;
}

/// Throws naming two vertex ids when the edges leave the poses in several components.
void checkConnected(const std::vector<Measurement>& ms, const std::vector<VertexId>& ids) {
  int components = 1;
  const int other = unconnectedPose(ms, static_cast<int>(ids.size()), &components);
  if (other < 0) return;
  throw InputError("certify: the graph is disconnected (" + std::to_string(components) +
                   " components; vertex " + std::to_string(ids[other]) +
                   " is not connected to vertex " + std::to_string(ids[0]) +
                   "); SE-Sync's relaxation needs one connected pose graph");
}

}  // namespace

PoseGraphProblem problemFromGraph(const Graph& graph) {
  const int d = checkVertices(graph);
  std::vector<VertexId> ids;
  std::map<VertexId, int> index;
  for (const auto& [id, v] : graph.vertices()) {
    index.emplace(id, static_cast<int>(ids.size()));
    ids.push_back(id);
  }
  std::vector<Measurement> ms;
  for (const auto& e : graph.edges()) {
    if (!e->active()) continue;
    ms.push_back(measurementOf(*e, d, index));
    if (ms.back().i == ms.back().j) {
      throw InputError("certify: " + edgeName(*e) + " joins a pose to itself");
    }
  }
  if (ids.size() < 2) throw InputError("certify: the graph needs at least two poses");
  checkConnected(ms, ids);
  return PoseGraphProblem{Problem(d, static_cast<int>(ids.size()), std::move(ms)), std::move(ids)};
}

}  // namespace graphslam::certify
