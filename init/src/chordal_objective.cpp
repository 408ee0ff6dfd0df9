// SPDX-License-Identifier: MIT
#include "graphslam/init/chordal_objective.h"

#include <cmath>
#include <memory>

#include "graphslam/diagnostics/information.h"
#include "graphslam/init/chordal_edges.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam3d/edges.h"

namespace graphslam::init {

namespace {

bool usable(double w) { return std::isfinite(w) && w > 0.0; }

/// The chordal edge replacing `e`, or null when `e` is not a relative-pose edge or its
/// weights are not positive.
std::unique_ptr<Edge> chordalEdge(const Edge& e, bool& skipped) {
  skipped = false;
  if (const auto* se2 = dynamic_cast<const types_slam2d::EdgeSE2*>(&e)) {
    const double tau = inverseTraceWeight(se2->information().topLeftCorner<2, 2>());
    const double kappa = se2->information()(2, 2);
    if (!usable(tau) || !usable(kappa)) return skipped = true, nullptr;
    auto c = std::make_unique<EdgeSE2Chordal>();
    c->setVertexIds(se2->vertexIds());
    c->setMeasurement(se2->measurement().toVector());
    c->setWeights(kappa, tau);
    return c;
  }
  if (const auto* se3 = dynamic_cast<const types_slam3d::EdgeSE3*>(&e)) {
    const double tau = inverseTraceWeight(se3->information().topLeftCorner<3, 3>());
    const double kappa = inverseTraceWeight(se3->information().bottomRightCorner<3, 3>()) / 2.0;
    if (!usable(tau) || !usable(kappa)) return skipped = true, nullptr;
    auto c = std::make_unique<EdgeSE3Chordal>();
    c->setVertexIds(se3->vertexIds());
    Eigen::Matrix<double, 12, 1> z;
    const Eigen::Matrix3d r = se3->measurement().rotation();
    z.head<9>() = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(r.data());
    z.tail<3>() = se3->measurement().translation();
    c->setMeasurement(z);
    c->setWeights(kappa, tau);
    return c;
  }
  return nullptr;
}

}  // namespace

ChordalObjective::ChordalObjective(Graph& graph) : graph_(&graph) {
  std::vector<Edge*> candidates;
  for (const auto& e : graph.edges()) {
    if (e->active()) candidates.push_back(e.get());
  }
  for (Edge* e : candidates) {
    bool skipped = false;
    auto c = chordalEdge(*e, skipped);
    skipped_ += skipped ? 1 : 0;
    if (!c) continue;
    chordal_.push_back(&graph.addEdge(std::move(c)));
    graph.setEdgeActive(*e, false);
    originals_.push_back(e);
  }
}

double ChordalObjective::value() const {
  double f = 0.0;
  for (Edge* e : chordal_) {
    e->computeError();
    f += e->chi2();
  }
  return f;
}

void ChordalObjective::restore() {
  if (chordal_.empty()) return;
  const std::vector<Edge*> added = chordal_;
  graph_->removeEdges([&added](const Edge& e) {
    for (const Edge* a : added) {
      if (a == &e) return true;
    }
    return false;
  });
  for (Edge* e : originals_) graph_->setEdgeActive(*e, true);
  chordal_.clear();
  originals_.clear();
}

}  // namespace graphslam::init
