// SPDX-License-Identifier: MIT
// Random one-edge graphs of every slam2d edge type, for the shared edge checks
// (tests/common/edge_type_checks.h), and small helpers to build graphs by hand.
#pragma once

#include <cmath>
#include <memory>
#include <random>
#include <utility>
#include <vector>

#include "graphslam/core/graph.h"
#include "graphslam/types_slam2d/edge_bearing_se2_xy.h"
#include "graphslam/types_slam2d/edge_pointxy.h"
#include "graphslam/types_slam2d/edge_prior_se2.h"
#include "graphslam/types_slam2d/edge_prior_se2_xy.h"
#include "graphslam/types_slam2d/edge_prior_xy.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/edge_se2_lotsofxy.h"
#include "graphslam/types_slam2d/edge_se2_offset.h"
#include "graphslam/types_slam2d/edge_se2_pointxy_offset.h"
#include "graphslam/types_slam2d/edge_se2_twopointsxy.h"
#include "graphslam/types_slam2d/edge_se2_xy.h"
#include "graphslam/types_slam2d/edge_se2_xy_calib.h"
#include "graphslam/types_slam2d/edge_xy_bearing_range.h"
#include "graphslam/types_slam2d/parameter_se2_offset.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"

namespace slam2d_test {

using namespace graphslam;
using namespace graphslam::types_slam2d;

inline constexpr double kPi = 3.14159265358979323846;

inline SE2 randomPose(std::mt19937& rng) {
  std::uniform_real_distribution<double> t(-10, 10), a(-kPi, kPi);
  return SE2(t(rng), t(rng), a(rng));
}
inline Eigen::Vector2d randomPoint(std::mt19937& rng) {
  std::uniform_real_distribution<double> t(-10, 10);
  return {t(rng), t(rng)};
}
/// A random symmetric positive definite d x d matrix (d = D unless D is Eigen::Dynamic).
template <int D>
Eigen::Matrix<double, D, D> randomInformation(std::mt19937& rng, int d = D) {
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::Matrix<double, D, D> a(d, d);
  for (int i = 0; i < d * d; ++i) a.data()[i] = u(rng);
  const Eigen::Matrix<double, D, D> m =
      a * a.transpose() + Eigen::Matrix<double, D, D>::Identity(d, d);
  return 0.5 * (m + m.transpose());  // exactly symmetric, as a file's upper triangle gives
}

/// A VertexSE2 `id` at `x` in `g`.
inline VertexSE2& addPose(Graph& g, VertexId id, const SE2& x) {
  auto v = std::make_unique<VertexSE2>();
  v->setId(id);
  v->setEstimate(x);
  return static_cast<VertexSE2&>(g.addVertex(std::move(v)));
}
/// A VertexXY `id` at `p` in `g`.
inline VertexXY& addPoint(Graph& g, VertexId id, const Eigen::Vector2d& p) {
  auto v = std::make_unique<VertexXY>();
  v->setId(id);
  v->setEstimate(p);
  return static_cast<VertexXY&>(g.addVertex(std::move(v)));
}
/// A PARAMS_SE2OFFSET `id` holding `offset` in `g`.
inline void addOffset(Graph& g, ParameterId id, const SE2& offset) {
  auto p = std::make_unique<ParameterSE2Offset>();
  p->setId(id);
  p->setValue(offset);
  g.addParameter(std::move(p));
}
/// Adds `e` (vertex and parameter ids set) with `z` and `info` to `g`; the edge, its error
/// computed.
template <typename E>
E& addEdge(Graph& g, std::unique_ptr<E> e, const typename E::Measurement& z,
           const typename E::InformationMatrix& info) {
  e->setMeasurement(z);
  e->setInformation(info);
  auto& edge = static_cast<E&>(g.addEdge(std::move(e)));
  edge.computeError();
  return edge;
}
/// A new edge of type E on `ids`.
template <typename E>
std::unique_ptr<E> newEdge(std::vector<VertexId> ids) {
  auto e = std::make_unique<E>();
  e->setVertexIds(std::move(ids));
  return e;
}

/// Builds a random graph holding one edge of type E and its vertices.
template <typename E>
struct EdgeFactory;

template <>
struct EdgeFactory<EdgeSE2> {
  static EdgeSE2* make(Graph& g, std::mt19937& rng) {
    addPose(g, 0, randomPose(rng));
    addPose(g, 1, randomPose(rng));
    return &addEdge(g, newEdge<EdgeSE2>({0, 1}), randomPose(rng), randomInformation<3>(rng));
  }
};

template <>
struct EdgeFactory<EdgeSE2XY> {
  static EdgeSE2XY* make(Graph& g, std::mt19937& rng) {
    addPose(g, 0, randomPose(rng));
    addPoint(g, 1, randomPoint(rng));
    return &addEdge(g, newEdge<EdgeSE2XY>({0, 1}), randomPoint(rng), randomInformation<2>(rng));
  }
};

/// A prior E on one vertex (id 0) at a random estimate, with a random measurement.
template <typename E, typename Random>
E* makePrior(Graph& g, std::mt19937& rng, Random random) {
  auto a = std::make_unique<typename E::template VertexXi<0>>();
  a->setId(0);
  a->setEstimate(random(rng));
  g.addVertex(std::move(a));
  auto e = std::make_unique<E>();
  e->setVertexIds({0});
  e->setMeasurement(random(rng));
  e->setInformation(randomInformation<E::kDimension>(rng));
  return static_cast<E*>(&g.addEdge(std::move(e)));
}

template <>
struct EdgeFactory<EdgePriorSE2> {
  static EdgePriorSE2* make(Graph& g, std::mt19937& rng) {
    return makePrior<EdgePriorSE2>(g, rng, randomPose);
  }
};

/// Two VertexXY at `r` (id 0) and `l` (id 1) and an edge E from r to l.
template <typename E>
E& pointEdge(Graph& g, const Eigen::Vector2d& r, const Eigen::Vector2d& l,
             const Eigen::Vector2d& z) {
  for (const auto& [id, p] : {std::pair{0, r}, std::pair{1, l}}) {
    auto v = std::make_unique<VertexXY>();
    v->setId(id);
    v->setEstimate(p);
    g.addVertex(std::move(v));
  }
  auto e = std::make_unique<E>();
  e->setVertexIds({0, 1});
  e->setMeasurement(z);
  auto& edge = static_cast<E&>(g.addEdge(std::move(e)));
  edge.computeError();
  return edge;
}

/// Two random VertexXY at least 0.5 apart, and edge E between them.
template <typename E>
E* makePointPair(Graph& g, std::mt19937& rng, const Eigen::Vector2d& measurement) {
  Eigen::Vector2d pa = randomPoint(rng), pb = randomPoint(rng);
  while ((pb - pa).norm() < 0.5) pb = randomPoint(rng);
  E& e = pointEdge<E>(g, pa, pb, measurement);
  e.setInformation(randomInformation<2>(rng));
  return &e;
}

template <>
struct EdgeFactory<EdgePointXY> {
  static EdgePointXY* make(Graph& g, std::mt19937& rng) {
    return makePointPair<EdgePointXY>(g, rng, randomPoint(rng));
  }
};

template <>
struct EdgeFactory<EdgeXYBearingRange> {
  static EdgeXYBearingRange* make(Graph& g, std::mt19937& rng) {
    // Bearings as in the homework's data: near the true one, not wrapped (k * 2 pi added).
    std::uniform_real_distribution<double> noise(-0.3, 0.3);
    std::uniform_int_distribution<int> turns(-1, 1);
    EdgeXYBearingRange* e = makePointPair<EdgeXYBearingRange>(g, rng, Eigen::Vector2d::Zero());
    const Eigen::Vector2d d = static_cast<const VertexXY*>(g.vertex(1))->estimate() -
                              static_cast<const VertexXY*>(g.vertex(0))->estimate();
    e->setMeasurement(Eigen::Vector2d(std::atan2(d.y(), d.x()) + noise(rng) + 2 * kPi * turns(rng),
                                      d.norm() + noise(rng)));
    return e;
  }
};

template <>
struct EdgeFactory<EdgePriorXY> {
  static EdgePriorXY* make(Graph& g, std::mt19937& rng) {
    return makePrior<EdgePriorXY>(g, rng, randomPoint);
  }
};

/// A random pose 0 and point 1 at least 0.5 apart.
inline void randomPoseAndPoint(Graph& g, std::mt19937& rng) {
  const SE2 x = randomPose(rng);
  Eigen::Vector2d l = randomPoint(rng);
  while ((l - x.translation()).norm() < 0.5) l = randomPoint(rng);
  addPose(g, 0, x);
  addPoint(g, 1, l);
}

template <>
struct EdgeFactory<EdgeSE2Offset> {
  static EdgeSE2Offset* make(Graph& g, std::mt19937& rng) {
    addPose(g, 0, randomPose(rng));
    addPose(g, 1, randomPose(rng));
    addOffset(g, 10, randomPose(rng));
    addOffset(g, 11, randomPose(rng));
    auto e = newEdge<EdgeSE2Offset>({0, 1});
    e->setParameterId(0, 10);
    e->setParameterId(1, 11);
    return &addEdge(g, std::move(e), randomPose(rng), randomInformation<3>(rng));
  }
};

template <>
struct EdgeFactory<EdgeSE2PointXYOffset> {
  static EdgeSE2PointXYOffset* make(Graph& g, std::mt19937& rng) {
    randomPoseAndPoint(g, rng);
    addOffset(g, 10, randomPose(rng));
    auto e = newEdge<EdgeSE2PointXYOffset>({0, 1});
    e->setParameterId(0, 10);
    return &addEdge(g, std::move(e), randomPoint(rng), randomInformation<2>(rng));
  }
};

template <>
struct EdgeFactory<EdgeBearingSE2XY> {
  static EdgeBearingSE2XY* make(Graph& g, std::mt19937& rng) {
    randomPoseAndPoint(g, rng);
    std::uniform_real_distribution<double> bearing(-kPi, kPi);
    return &addEdge(g, newEdge<EdgeBearingSE2XY>({0, 1}), bearing(rng), randomInformation<1>(rng));
  }
};

template <>
struct EdgeFactory<EdgeSE2XYCalib> {
  static EdgeSE2XYCalib* make(Graph& g, std::mt19937& rng) {
    randomPoseAndPoint(g, rng);
    addPose(g, 2, randomPose(rng));
    return &addEdge(g, newEdge<EdgeSE2XYCalib>({0, 1, 2}), randomPoint(rng),
                    randomInformation<2>(rng));
  }
};

template <>
struct EdgeFactory<EdgePriorSE2XY> {
  static EdgePriorSE2XY* make(Graph& g, std::mt19937& rng) {
    addPose(g, 0, randomPose(rng));
    return &addEdge(g, newEdge<EdgePriorSE2XY>({0}), randomPoint(rng), randomInformation<2>(rng));
  }
};

template <>
struct EdgeFactory<EdgeSE2TwoPointsXY> {
  static EdgeSE2TwoPointsXY* make(Graph& g, std::mt19937& rng) {
    addPose(g, 0, randomPose(rng));
    addPoint(g, 1, randomPoint(rng));
    addPoint(g, 2, randomPoint(rng));
    const Eigen::Vector4d z(randomPoint(rng).x(), randomPoint(rng).y(), randomPoint(rng).x(),
                            randomPoint(rng).y());
    return &addEdge(g, newEdge<EdgeSE2TwoPointsXY>({0, 1, 2}), z, randomInformation<4>(rng));
  }
};

template <>
struct EdgeFactory<EdgeSE2LotsOfXY> {
  /// A pose and 1 to 4 points.
  static EdgeSE2LotsOfXY* make(Graph& g, std::mt19937& rng) {
    const int points = std::uniform_int_distribution<int>(1, 4)(rng);
    addPose(g, 0, randomPose(rng));
    std::vector<VertexId> ids{0};
    Eigen::VectorXd z(2 * points);
    for (int i = 1; i <= points; ++i) {
      addPoint(g, i, randomPoint(rng));
      ids.push_back(i);
      z.segment<2>(2 * (i - 1)) = randomPoint(rng);
    }
    return &addEdge(g, newEdge<EdgeSE2LotsOfXY>(ids), z,
                    randomInformation<Eigen::Dynamic>(rng, 2 * points));
  }
};

}  // namespace slam2d_test
