// SPDX-License-Identifier: MIT
// One self-contained web page to explore a 2D or 3D graph: its data (positions, edges,
// per-edge chi2, iterations, ground truth, covariances), the project's own viewer script and
// style (view/web/, embedded into this library at build time) in one HTML file that opens
// from disk with no network and no server.
//
//   view::Scene scene(graph, types);              // the graph's current estimate: "optimised"
//   scene.setInitial(view::captureEstimates(graph_before, "initial"));
//   scene.setSourceLines("intel.g2o", in.vertex_lines, in.edge_lines);
//   scene.writePage("intel.html");                // atomic; throws graphslam::Error
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "graphslam/core/graph.h"
#include "graphslam/core/type_registry.h"

namespace graphslam::view {

/// How the page draws a vertex.
enum class VertexKind : unsigned char {
  kPose = 0,     ///< a pose (VERTEX_SE2, VERTEX_SE3:QUAT, VERTEX_VEHICLE)
  kPoint = 1,    ///< a landmark (VERTEX_XY, VERTEX_TRACKXYZ, VERTEX_LANDMARK)
  kGeneric = 2,  ///< a type the viewer does not know: its first 2 (3D: 3) estimate values
};

/// The layer an edge is drawn in.
enum class EdgeKind : unsigned char {
  kOdometry = 0,     ///< between poses of consecutive ids
  kLoopClosure = 1,  ///< between other poses
  kLandmark = 2,     ///< touching a landmark
  kPrior = 3,        ///< on one vertex
  kOther = 4,        ///< touching a generic vertex
};

/// Tuning of the page; every field is a bound on its size or a threshold of its marks.
struct Options {
  std::string title;  ///< shown in the page's title and panel; "graph" when empty
  /// At most this many iteration frames are written (evenly chosen, the first and last
  /// kept): each costs the positions and per-edge chi2 of the whole graph.
  std::size_t max_frames = 100;
  /// Frames are dropped (evenly) so that all of them together stay below this many bytes.
  std::size_t max_frame_bytes = std::size_t{64} << 20;
  /// Above this many edges the page draws a subsample while the view moves (level of
  /// detail) and every edge once it rests.
  std::size_t lod_edges = 200000;
  /// Up to this many edges the page holds every edge's error vector at the current
  /// estimate (shown when an edge is picked); above it, only their chi2.
  std::size_t max_error_edges = 200000;
  /// An edge whose robust weight rho'(chi2) is below this is marked down-weighted.
  double downweight_below = 0.5;
};

/// Every vertex's flat estimate data (Vertex::getEstimateData) in graph vertex order: the
/// state of one iteration.
struct Snapshot {
  std::string label;
  double chi2 = 0.0;  ///< the objective the optimizer reported (NaN: unknown)
  std::vector<double> data;
};

/// The estimates of `graph` now.
[[nodiscard]] Snapshot captureEstimates(const Graph& graph, std::string label, double chi2 = 0.0);

/// A graph and what comes with it, written as one page.
class Scene {
 public:
  /// Keeps references to `graph` and `types` (which must outlive the scene). Throws
  /// graphslam::InputError for a graph with no vertices.
  Scene(Graph& graph, const TypeRegistry& types, Options options = {});

  /// The file the graph came from and the line of each vertex and edge (io::GraphFile's
  /// vertex_lines, edge_lines; edge lines are used only when one per edge).
  void setSourceLines(std::string path,
                      const std::vector<std::pair<VertexId, std::size_t>>& vertex_lines,
                      const std::vector<std::size_t>& edge_lines);
  /// The estimate before optimisation, drawn beside or over the current one.
  void setInitial(Snapshot initial);
  /// One optimizer iteration; the slider steps through them in the order added.
  void addIteration(Snapshot frame);
  /// The true position of vertices and their absolute position error (APE), coloured per
  /// pose as evo does; vertices without one are left out.
  void setGroundTruth(const std::map<VertexId, Eigen::Vector3d>& truth,
                      const std::map<VertexId, double>& ape);
  /// The marginal covariance of a vertex (its block of H^-1 in the vertex's update
  /// coordinates; the position part, the first 2 or 3 rows and columns, is drawn as an
  /// ellipse or ellipsoid at 3 sigma).
  void addCovariance(VertexId id, const Eigen::MatrixXd& block);
  /// An edge removed from the graph as an outlier (GNC): drawn and marked as rejected.
  void addRejectedEdge(const std::vector<VertexId>& ids, const std::string& tag, double chi2,
                       std::size_t line);
  /// A line of the summary panel (the optimizer's status, timings, ...).
  void addSummary(std::string key, std::string value);

  /// The page as text. Throws graphslam::InputError naming vertex ids whose estimate is not
  /// finite. Computes every edge's error at the graph's current estimate (and at each frame's,
  /// restoring the current one).
  [[nodiscard]] std::string html();
  /// html() written to `path` atomically: on any error nothing is left at `path`. Throws
  /// graphslam::Error naming the path (a missing folder among the reasons).
  void writePage(const std::string& path);

  struct Data;  ///< the arrays of the page (view/src/)

 private:
  void addRejectedArrays(Data& d) const;
  /// The initial estimate, the kept iterations and `current` (restored at the end).
  void addFrames(Data& d, const Snapshot& current, std::vector<float> current_chi2);
  void addTruth(Data& d) const;
  [[nodiscard]] std::string covarianceJson(const Data& d) const;
  Graph& graph_;
  const TypeRegistry& types_;
  Options options_;
  std::string source_;
  std::map<VertexId, std::size_t> vertex_lines_;
  std::vector<std::size_t> edge_lines_;
  Snapshot initial_;
  std::vector<Snapshot> frames_;
  std::map<VertexId, Eigen::Vector3d> truth_;
  std::map<VertexId, double> ape_;
  std::map<VertexId, Eigen::MatrixXd> covariances_;
  struct Rejected {
    std::vector<VertexId> ids;
    std::string tag;
    double chi2;
    std::size_t line;
  };
  std::vector<Rejected> rejected_;
  std::vector<std::pair<std::string, std::string>> summary_;
};

}  // namespace graphslam::view
