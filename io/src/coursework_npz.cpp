// SPDX-License-Identifier: MIT
#include "graphslam/io/coursework_npz.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>

#include "graphslam/io/npz.h"
#include "graphslam/support/error.h"
#include "graphslam/types_slam2d/edge_pointxy.h"
#include "graphslam/types_slam2d/edge_prior_xy.h"
#include "graphslam/types_slam2d/edge_xy_bearing_range.h"
#include "graphslam/types_slam2d/vertex_xy.h"

namespace graphslam::io {

using namespace graphslam::types_slam2d;

namespace {

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

struct Reader {
  const io::NpzArchive& npz;

  [[noreturn]] void fail(const std::string& array, const std::string& message) const {
    throw InputError(npz.path() + ": array '" + array + "': " + message);
  }

  /// A 2-d array with `cols` columns (and `rows` rows unless negative), all finite.
  RowMatrix matrix(const std::string& name, long rows, long cols) const {
    if (!npz.contains(name)) {
      throw InputError(npz.path() + ": array '" + name +
                       "' is missing (a CMU 16-833 homework file has odom, observations, "
                       "sigma_odom, sigma_landmark, gt_traj, gt_landmarks)");
    }
    const io::NpyArray a = npz.read(name);
    const bool shape_ok = a.shape.size() == 2 && static_cast<long>(a.shape[1]) == cols &&
                          (rows < 0 || static_cast<long>(a.shape[0]) == rows);
    // An empty odometry list may be saved with shape (0,).
    const bool empty_ok = a.shape.size() == 1 && a.shape[0] == 0 && rows <= 0;
    if (!shape_ok && !empty_ok) {
      fail(name, "shape " + a.shapeString() + ", expected (" +
                     (rows < 0 ? std::string("N") : std::to_string(rows)) + ", " +
                     std::to_string(cols) + ")");
    }
    const long n = empty_ok ? 0 : static_cast<long>(a.shape[0]);
    RowMatrix m(n, cols);
    for (long i = 0; i < n; ++i) {
      for (long j = 0; j < cols; ++j) {
        const double v = a.at(static_cast<std::size_t>(i), static_cast<std::size_t>(j));
        if (!std::isfinite(v)) {
          fail(name, "row " + std::to_string(i) + " column " + std::to_string(j) + " is " +
                         (std::isnan(v) ? "NaN" : "infinite"));
        }
        m(i, j) = v;
      }
    }
    return m;
  }

  /// A 2x2 symmetric positive definite covariance; returns its inverse.
  Eigen::Matrix2d information(const std::string& name, Eigen::Matrix2d& sigma) const {
    sigma = matrix(name, 2, 2);
    if (std::abs(sigma(0, 1) - sigma(1, 0)) > 1e-12 * sigma.cwiseAbs().maxCoeff()) {
      fail(name, "covariance is not symmetric");
    }
    const Eigen::LLT<Eigen::Matrix2d> llt(sigma);
    if (llt.info() != Eigen::Success || sigma(0, 0) <= 0 || sigma(1, 1) <= 0) {
      fail(name, "covariance is not positive definite");
    }
    return sigma.inverse();
  }

  /// Index column of an observation row: an integer in [0, limit).
  int index(double value, std::size_t row, const char* what, int limit) const {
    if (value != std::floor(value)) {
      std::ostringstream msg;
      msg.precision(17);
      msg << "row " << row << ": " << what << " index " << value << " is not an integer";
      fail("observations", msg.str());
    }
    if (value < 0 || value >= limit) {
      std::ostringstream msg;
      msg << "row " << row << ": " << what << " index " << value << " is out of range [0, " << limit
          << ")";
      fail("observations", msg.str());
    }
    return static_cast<int>(value);
  }
};

/// Mean squared residual of the observations at the ground truth, per model.
double meanSquaredResidual(const RowMatrix& obs, const RowMatrix& traj, const RowMatrix& lms,
                           bool bearing_range) {
  double sum = 0.0;
  for (Eigen::Index k = 0; k < obs.rows(); ++k) {
    const Eigen::Vector2d d = lms.row(static_cast<Eigen::Index>(obs(k, 1))).transpose() -
                              traj.row(static_cast<Eigen::Index>(obs(k, 0))).transpose();
    Eigen::Vector2d r;
    if (bearing_range) {
      r << normalizeAngle(obs(k, 2) - std::atan2(d.y(), d.x())), obs(k, 3) - d.norm();
    } else {
      r << obs(k, 2) - d.x(), obs(k, 3) - d.y();
    }
    sum += r.squaredNorm();
  }
  return obs.rows() ? sum / static_cast<double>(obs.rows()) : 0.0;
}

template <typename E>
void addEdge(Graph& g, VertexId a, VertexId b, const Eigen::Vector2d& z,
             const Eigen::Matrix2d& info) {
  auto e = std::make_unique<E>();
  e->setVertexIds({a, b});
  e->setMeasurement(z);
  e->setInformation(info);
  g.addEdge(std::move(e));
}

/// The rows of the homework's arrays: odometry, observations (pose, landmark, z) and the
/// pose and landmark index of each observation.
struct Rows {
  RowMatrix odom, obs;
  std::vector<int> pose_of, landmark_of;
};

/// The observation model: the requested one, else the one the observations fit at the
/// ground truth, else the file name's ("nonlinear"). Sets p.model and p.model_reason.
void chooseModel(CourseworkProblem& p, const CourseworkNpzOptions& options, const std::string& path,
                 const RowMatrix& obs, const RowMatrix* gt_traj, const RowMatrix* gt_landmarks) {
  p.model = options.model;
  if (p.model != PointObservationModel::kAuto) {
    p.model_reason = "requested";
    return;
  }
  if (gt_traj && gt_landmarks && obs.rows() > 0) {
    const double lin = meanSquaredResidual(obs, *gt_traj, *gt_landmarks, false);
    const double br = meanSquaredResidual(obs, *gt_traj, *gt_landmarks, true);
    p.model = br < lin ? PointObservationModel::kBearingRange : PointObservationModel::kLinear;
    std::ostringstream why;
    why.precision(3);
    why << "the observations fit the " << toString(p.model)
        << " model at the ground truth (RMS residual " << std::sqrt(std::min(lin, br))
        << ", against " << std::sqrt(std::max(lin, br)) << " for the "
        << (br < lin ? "linear" : "bearing-range") << " one)";
    p.model_reason = why.str();
    return;
  }
  const std::string base = path.substr(path.find_last_of('/') + 1);
  const bool nonlinear = base.find("nonlinear") != std::string::npos;
  p.model = nonlinear ? PointObservationModel::kBearingRange : PointObservationModel::kLinear;
  p.model_reason = std::string("no ground truth to test the models against; the file name ") +
                   (nonlinear ? "contains" : "does not contain") + " \"nonlinear\"";
}

/// The vertices with the homework's initial guess: zero for the linear model; for the
/// bearing-range one, poses by dead reckoning and each landmark from its first
/// observation. Returns how many landmarks are never observed.
std::size_t addVertices(CourseworkProblem& p, const Rows& r, bool bearing_range) {
  std::vector<Eigen::Vector2d> traj(static_cast<std::size_t>(p.num_poses), Eigen::Vector2d::Zero());
  std::vector<Eigen::Vector2d> lms(static_cast<std::size_t>(p.num_landmarks),
                                   Eigen::Vector2d::Zero());
  std::vector<char> seen(lms.size(), 0);
  if (bearing_range) {
    for (Eigen::Index i = 0; i < r.odom.rows(); ++i) {
      traj[static_cast<std::size_t>(i) + 1] =
          traj[static_cast<std::size_t>(i)] + r.odom.row(i).transpose();
    }
  }
  for (Eigen::Index k = 0; k < r.obs.rows(); ++k) {
    const auto l = static_cast<std::size_t>(r.landmark_of[static_cast<std::size_t>(k)]);
    if (seen[l]) continue;
    seen[l] = 1;
    if (bearing_range) {
      const Eigen::Vector2d& x =
          traj[static_cast<std::size_t>(r.pose_of[static_cast<std::size_t>(k)])];
      lms[l] = x + r.obs(k, 3) * Eigen::Vector2d(std::cos(r.obs(k, 2)), std::sin(r.obs(k, 2)));
    }
  }
  auto add_vertex = [&](VertexId id, const Eigen::Vector2d& x) {
    auto v = std::make_unique<VertexXY>();
    v->setId(id);
    v->setEstimate(x);
    p.graph.addVertex(std::move(v));
  };
  for (int i = 0; i < p.num_poses; ++i) add_vertex(CourseworkProblem::poseId(i), traj[i]);
  for (int j = 0; j < p.num_landmarks; ++j) add_vertex(p.landmarkId(j), lms[j]);
  std::size_t unobserved = 0;
  for (char s : seen) unobserved += s ? 0 : 1;
  return unobserved;
}

/// The edges, in the homework's row order: prior, odometry, observations.
void addEdges(CourseworkProblem& p, const Rows& r, const CourseworkNpzOptions& options,
              const Eigen::Matrix2d& info_odom, const Eigen::Matrix2d& info_obs,
              bool bearing_range) {
  auto prior = std::make_unique<EdgePriorXY>();
  prior->setVertexIds({CourseworkProblem::poseId(0)});
  prior->setMeasurement(Eigen::Vector2d::Zero());
  prior->setInformation(options.prior_information);
  p.graph.addEdge(std::move(prior));
  for (Eigen::Index i = 0; i < r.odom.rows(); ++i) {
    addEdge<EdgePointXY>(p.graph, static_cast<VertexId>(i), static_cast<VertexId>(i + 1),
                         r.odom.row(i).transpose(), info_odom);
  }
  for (Eigen::Index k = 0; k < r.obs.rows(); ++k) {
    const auto row = static_cast<std::size_t>(k);
    const VertexId a = CourseworkProblem::poseId(r.pose_of[row]);
    const VertexId b = p.landmarkId(r.landmark_of[row]);
    const Eigen::Vector2d z(r.obs(k, 2), r.obs(k, 3));
    if (bearing_range) {
      addEdge<EdgeXYBearingRange>(p.graph, a, b, z, info_obs);
    } else {
      addEdge<EdgePointXY>(p.graph, a, b, z, info_obs);
    }
  }
}

}  // namespace

const char* toString(PointObservationModel model) {
  switch (model) {
    case PointObservationModel::kAuto:
      return "auto";
    case PointObservationModel::kLinear:
      return "linear";
    case PointObservationModel::kBearingRange:
      return "bearing-range";
  }
  return "?";
}

CourseworkProblem loadCourseworkNpz(const std::string& path, const CourseworkNpzOptions& options) {
  return loadCourseworkNpz(NpzArchive(path), options);
}

CourseworkProblem loadCourseworkNpz(const NpzArchive& npz, const CourseworkNpzOptions& options) {
  const Reader in{npz};
  CourseworkProblem p;

  Rows r;
  r.odom = in.matrix("odom", -1, 2);
  r.obs = in.matrix("observations", -1, 4);
  const Eigen::Matrix2d info_odom = in.information("sigma_odom", p.sigma_odom);
  const Eigen::Matrix2d info_obs = in.information("sigma_landmark", p.sigma_landmark);
  p.num_poses = static_cast<int>(r.odom.rows()) + 1;
  p.num_odometry = static_cast<std::size_t>(r.odom.rows());
  p.num_observations = static_cast<std::size_t>(r.obs.rows());

  const bool has_traj = npz.contains("gt_traj");
  const bool has_landmarks = npz.contains("gt_landmarks");
  RowMatrix gt_traj, gt_landmarks;
  if (has_traj) gt_traj = in.matrix("gt_traj", p.num_poses, 2);
  if (has_landmarks) {
    gt_landmarks = in.matrix("gt_landmarks", -1, 2);
    p.num_landmarks = static_cast<int>(gt_landmarks.rows());
  } else {
    double largest = -1;
    for (Eigen::Index k = 0; k < r.obs.rows(); ++k) largest = std::max(largest, r.obs(k, 1));
    if (largest >= std::numeric_limits<int>::max() - p.num_poses) {
      in.fail("observations", "landmark index " + std::to_string(largest) + " is too large");
    }
    p.num_landmarks = static_cast<int>(std::floor(largest)) + 1;
  }
  r.pose_of.resize(static_cast<std::size_t>(r.obs.rows()));
  r.landmark_of.resize(r.pose_of.size());
  for (Eigen::Index k = 0; k < r.obs.rows(); ++k) {
    const auto row = static_cast<std::size_t>(k);
    r.pose_of[row] = in.index(r.obs(k, 0), row, "pose", p.num_poses);
    r.landmark_of[row] = in.index(r.obs(k, 1), row, "landmark", p.num_landmarks);
  }

  chooseModel(p, options, npz.path(), r.obs, has_traj ? &gt_traj : nullptr,
              has_landmarks ? &gt_landmarks : nullptr);
  const bool bearing_range = p.model == PointObservationModel::kBearingRange;
  const std::size_t unobserved = addVertices(p, r, bearing_range);
  addEdges(p, r, options, info_odom, info_obs, bearing_range);
  if (unobserved) {
    p.notes.push_back(std::to_string(unobserved) +
                      " landmark(s) are never observed; their vertices have no edges");
  }
  if (has_traj) {
    for (int i = 0; i < p.num_poses; ++i) {
      p.ground_truth.pose_ids.push_back(CourseworkProblem::poseId(i));
      p.ground_truth.poses.emplace_back(gt_traj.row(i).transpose());
    }
  }
  if (has_landmarks) {
    for (int j = 0; j < p.num_landmarks; ++j) {
      p.ground_truth.landmark_ids.push_back(p.landmarkId(j));
      p.ground_truth.landmarks.emplace_back(gt_landmarks.row(j).transpose());
    }
  }
  return p;
}

}  // namespace graphslam::io
