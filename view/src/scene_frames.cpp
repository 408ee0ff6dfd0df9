// SPDX-License-Identifier: MIT
// The parts of a page beyond the graph's structure: frames (initial estimate, iterations),
// rejected edges, ground truth and covariance ellipses.
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "graphslam/support/error.h"
#include "scene_data.h"

namespace graphslam::view {

namespace {

/// Indices of the frames kept: all when they fit, otherwise evenly spaced, first and last kept.
std::vector<std::size_t> keptFrames(std::size_t count, std::size_t max_count) {
  std::vector<std::size_t> kept;
  if (count == 0 || max_count == 0) return kept;
  if (count <= max_count) {
    for (std::size_t i = 0; i < count; ++i) kept.push_back(i);
    return kept;
  }
  for (std::size_t k = 0; k < max_count; ++k) {
    const std::size_t i = max_count == 1 ? count - 1 : k * (count - 1) / (max_count - 1);
    if (kept.empty() || kept.back() != i) kept.push_back(i);
  }
  return kept;
}

/// The principal axes (columns, scaled by the standard deviations) of the position block of
/// `cov` for a vertex whose estimate data is `x` (a VERTEX_SE3:QUAT's translation update is in
/// its own frame: rotated into the world's).
Eigen::MatrixXd positionAxes(const Eigen::MatrixXd& cov, int dim, const std::string& tag,
                             const std::vector<double>& x) {
  Eigen::MatrixXd c = cov.topLeftCorner(dim, dim);
  if (tag == "VERTEX_SE3:QUAT" && x.size() >= 7) {
    const Eigen::Matrix3d r =
        Eigen::Quaterniond(x[6], x[3], x[4], x[5]).normalized().toRotationMatrix();
    c = r * c * r.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (c + c.transpose()));
  Eigen::MatrixXd axes = eig.eigenvectors();
  for (int k = 0; k < dim; ++k) axes.col(k) *= std::sqrt(std::max(0.0, eig.eigenvalues()(k)));
  return axes;
}

std::string numberText(double x) {
  if (!std::isfinite(x)) return "null";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.7g", x);
  return buf;
}

}  // namespace

void Scene::addRejectedArrays(Data& d) const {
  for (const Rejected& r : rejected_) {
    std::vector<std::uint32_t> idx;
    bool point = false;
    for (VertexId id : r.ids) {
      idx.push_back(static_cast<std::uint32_t>(std::lower_bound(d.vid.begin(), d.vid.end(), id) -
                                               d.vid.begin()));
      point = point || d.tag_kinds[d.vtag[idx.back()]] == VertexKind::kPoint;
    }
    const auto k = static_cast<std::uint32_t>(d.ea.size());
    d.ea.push_back(idx[0]);
    d.eb.push_back(idx.size() > 1 ? idx[1] : idx[0]);
    for (std::size_t s = 2; s < idx.size(); ++s) {
      d.xedge.push_back(k);
      d.xvertex.push_back(idx[s]);
    }
    const EdgeKind kind = idx.size() == 1 ? EdgeKind::kPrior
                          : point         ? EdgeKind::kLandmark
                                          : EdgeKind::kLoopClosure;
    d.ekind.push_back(static_cast<std::uint8_t>(kind));
    d.etag.push_back(tagIndex(d.edge_tags, r.tag));
    d.eflag.push_back(kFlagInactive | kFlagRemoved);
    d.eweight.push_back(0.0f);
    d.eline.push_back(static_cast<std::int32_t>(r.line));
  }
}

void Scene::addFrames(Data& d, const Snapshot& current, std::vector<float> current_chi2) {
  const std::size_t per_frame =
      (graph_.numVertices() * static_cast<std::size_t>(d.dim) + d.ea.size()) * sizeof(float);
  const std::size_t by_bytes = options_.max_frame_bytes / std::max<std::size_t>(per_frame, 1);
  const std::size_t fixed = 1 + (initial_.data.empty() ? 0 : 1);
  const std::size_t room = by_bytes > fixed ? by_bytes - fixed : 0;
  std::vector<const Snapshot*> shown;
  if (!initial_.data.empty()) shown.push_back(&initial_);
  for (std::size_t i : keptFrames(frames_.size(), std::min(options_.max_frames, room))) {
    shown.push_back(&frames_[i]);
  }
  auto push = [&](const Snapshot& s, std::vector<float> chi2) {
    for (const Rejected& r : rejected_) chi2.push_back(static_cast<float>(r.chi2));
    d.frame_pos.push_back(positionsOf(s.data, graph_, d.dim));
    d.frame_chi2.push_back(std::move(chi2));
    d.frame_labels.push_back(s.label);
    d.frame_objective.push_back(s.chi2);
  };
  try {
    for (const Snapshot* s : shown) {
      restoreEstimates(graph_, *s);
      push(*s, edgeChi2(graph_));
    }
  } catch (...) {
    restoreEstimates(graph_, current);
    throw;
  }
  restoreEstimates(graph_, current);
  (void)edgeChi2(graph_);  // the edges' stored errors as they were
  push(current, std::move(current_chi2));
  d.has_initial = !initial_.data.empty();
}

void Scene::addTruth(Data& d) const {
  if (truth_.empty()) return;
  const auto dim = static_cast<std::size_t>(d.dim);
  d.truth_pos.assign(d.vid.size() * dim, std::numeric_limits<float>::quiet_NaN());
  d.ape.assign(d.vid.size(), std::numeric_limits<float>::quiet_NaN());
  for (std::size_t i = 0; i < d.vid.size(); ++i) {
    const auto t = truth_.find(d.vid[i]);
    if (t != truth_.end()) {
      for (std::size_t c = 0; c < dim; ++c)
        d.truth_pos[i * dim + c] = static_cast<float>(t->second(c));
    }
    const auto a = ape_.find(d.vid[i]);
    if (a != ape_.end()) d.ape[i] = static_cast<float>(a->second);
  }
}

std::string Scene::covarianceJson(const Data& d) const {
  std::string extra = ",\"covariances\":[";
  std::size_t n = 0;
  for (const auto& [id, block] : covariances_) {
    const Vertex& v = *graph_.vertex(id);
    std::vector<double> x(static_cast<std::size_t>(v.estimateDataDimension()));
    v.getEstimateData(x.data());
    if (block.rows() < d.dim || block.cols() < d.dim) continue;
    const Eigen::MatrixXd axes = positionAxes(block, d.dim, vertexTag(types_, v), x);
    const auto idx =
        static_cast<std::size_t>(std::lower_bound(d.vid.begin(), d.vid.end(), id) - d.vid.begin());
    extra += std::string(n++ ? "," : "") + "{\"v\":" + std::to_string(idx) + ",\"axes\":[";
    for (int c = 0; c < d.dim; ++c) {
      for (int r = 0; r < d.dim; ++r) extra += (c || r ? "," : "") + numberText(axes(r, c));
    }
    extra += "]}";
  }
  return extra + "]";
}

}  // namespace graphslam::view
