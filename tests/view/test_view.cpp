// SPDX-License-Identifier: MIT
// The view module's page: its data (decoded back from the page), refusals, atomic writing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "graphslam/core/base_vertex.h"
#include "graphslam/core/graph.h"
#include "graphslam/core/type_registry.h"
#include "graphslam/support/error.h"
#include "graphslam/types_slam2d/edge_prior_se2.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/edge_se2_xy.h"
#include "graphslam/types_slam2d/register.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"
#include "graphslam/types_slam3d/register.h"
#include "graphslam/types_slam3d/vertex_se3.h"
#include "graphslam/view/scene.h"

using namespace graphslam;
namespace fs = std::filesystem;

namespace {

/// A vertex type the viewer does not know.
class VertexOdd final : public BaseVertex<2, Eigen::Vector2d> {
 public:
  [[nodiscard]] Eigen::Vector2d plus(const Eigen::Vector2d& x,
                                     const TangentVector& d) const override {
    return x + d;
  }
};

std::vector<unsigned char> unbase64(const std::string& s) {
  std::vector<unsigned char> out;
  unsigned v = 0;
  int bits = 0;
  for (const char c : s) {
    const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    const char* p = std::strchr(table, c);
    if (c == '=' || !p) break;
    v = (v << 6) | static_cast<unsigned>(p - table);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<unsigned char>((v >> bits) & 255));
    }
  }
  return out;
}

/// The array `name` of the page's data (the first one: frames hold "pos" and "chi2" again).
template <typename T>
std::vector<T> field(const std::string& page, const std::string& name, std::size_t from = 0) {
  const std::string key = "\"" + name + "\":\"";
  const std::size_t at = page.find(key, from);
  if (at == std::string::npos) return {};
  const std::size_t start = at + key.size();
  const auto bytes = unbase64(page.substr(start, page.find('"', start) - start));
  std::vector<T> v(bytes.size() / sizeof(T));
  std::memcpy(v.data(), bytes.data(), v.size() * sizeof(T));
  return v;
}

struct View_Page : ::testing::Test {
  TypeRegistry types;
  Graph graph;
  void SetUp() override {
    types_slam2d::registerTypes(types);
    // Poses 0..3 on a square, landmark 10, odometry 0-1-2-3, loop 3-0, prior on 0.
    const double xy[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int i = 0; i < 4; ++i) {
      auto v = std::make_unique<types_slam2d::VertexSE2>();
      v->setId(i);
      const double d[3] = {xy[i][0], xy[i][1], 0.0};
      v->setEstimateData(d);
      graph.addVertex(std::move(v));
    }
    auto l = std::make_unique<types_slam2d::VertexXY>();
    l->setId(10);
    const double p[2] = {0.5, 2.0};
    l->setEstimateData(p);
    graph.addVertex(std::move(l));
    auto edge = [&](std::unique_ptr<Edge> e, std::vector<VertexId> ids) {
      e->setVertexIds(ids);
      graph.addEdge(std::move(e));
    };
    for (int i = 0; i < 3; ++i) edge(std::make_unique<types_slam2d::EdgeSE2>(), {i, i + 1});
    edge(std::make_unique<types_slam2d::EdgeSE2>(), {3, 0});
    edge(std::make_unique<types_slam2d::EdgeSE2XY>(), {2, 10});
    edge(std::make_unique<types_slam2d::EdgePriorSE2>(), {0});
  }
};

}  // namespace

TEST_F(View_Page, PageHoldsTheGraphAndItsScript) {
  view::Options options;
  options.title = "square </script><b>";
  view::Scene scene(graph, types, options);
  scene.setSourceLines("square.g2o", {{0, 1}, {1, 2}, {10, 9}}, {11, 12, 13, 14, 15, 16});
  const std::string page = scene.html();
  EXPECT_EQ(page.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_NE(page.find("WebGL"), std::string::npos);             // the embedded script
  EXPECT_NE(page.find("#panel"), std::string::npos);            // the embedded style
  EXPECT_EQ(page.find("square </script>"), std::string::npos);  // the title is escaped
  EXPECT_EQ(page.find("http://"), std::string::npos);           // nothing to fetch
  EXPECT_EQ(page.find("https://"), std::string::npos);
  EXPECT_NE(page.find("\"dim\":2"), std::string::npos);
  EXPECT_EQ(field<std::int32_t>(page, "vid"), (std::vector<std::int32_t>{0, 1, 2, 3, 10}));
  EXPECT_EQ(field<std::int32_t>(page, "vline"), (std::vector<std::int32_t>{1, 2, 0, 0, 9}));
  EXPECT_EQ(field<std::uint8_t>(page, "ekind"), (std::vector<std::uint8_t>{0, 0, 0, 1, 2, 3}));
  EXPECT_EQ(field<std::int32_t>(page, "eline"),
            (std::vector<std::int32_t>{11, 12, 13, 14, 15, 16}));
  const auto pos = field<float>(page, "pos");
  ASSERT_EQ(pos.size(), 10u);
  EXPECT_FLOAT_EQ(pos[8], 0.5f);
  EXPECT_FLOAT_EQ(pos[9], 2.0f);
  // chi2 of each edge at the estimate: the odometry measured 0 but the poses are 1 apart.
  graph.edges()[0]->computeError();
  const auto chi2 = field<float>(page, "chi2");
  ASSERT_EQ(chi2.size(), 6u);
  EXPECT_FLOAT_EQ(chi2[0], static_cast<float>(graph.edges()[0]->chi2()));
  EXPECT_GT(chi2[0], 0.0f);
  EXPECT_EQ(field<std::uint8_t>(page, "edim").size(), 6u);
}

TEST_F(View_Page, IterationsAreFramesAndTheEstimateIsRestored) {
  view::Options options;
  options.max_frames = 3;
  view::Scene scene(graph, types, options);
  const view::Snapshot now = view::captureEstimates(graph, "now");
  scene.setInitial(now);
  for (int k = 0; k < 10; ++k) {
    view::Snapshot s = now;
    s.label = "iteration " + std::to_string(k + 1);
    s.data[0] = k;  // vertex 0's x
    scene.addIteration(s);
  }
  const std::string page = scene.html();
  // initial, 3 iterations (first, middle, last), the current estimate.
  std::size_t frames = 0;
  for (std::size_t at = page.find("\"label\":"); at != std::string::npos;
       at = page.find("\"label\":", at + 1))
    ++frames;
  EXPECT_EQ(frames, 5u);
  EXPECT_NE(page.find("iteration 10"), std::string::npos);
  EXPECT_NE(page.find("iteration 1\""), std::string::npos);
  EXPECT_EQ(page.find("iteration 2\""), std::string::npos);
  EXPECT_EQ(view::captureEstimates(graph, "after").data, now.data);
}

TEST_F(View_Page, RejectedAndInactiveEdgesAreMarked) {
  graph.setEdgeActive(*graph.edges()[3], false);
  view::Scene scene(graph, types);
  scene.addRejectedEdge({1, 3}, "EDGE_SE2", 123.0, 40);
  const std::string page = scene.html();
  const auto flags = field<std::uint8_t>(page, "eflag");
  ASSERT_EQ(flags.size(), 7u);
  EXPECT_EQ(flags[3] & 1, 1);  // inactive
  EXPECT_EQ(flags[6], 1 | 8);  // removed as an outlier
  EXPECT_EQ(field<std::int32_t>(page, "eline").back(), 40);
  EXPECT_EQ(field<float>(page, "chi2").back(), 123.0f);
  EXPECT_THROW(scene.addRejectedEdge({1, 99}, "EDGE_SE2", 1.0, 0), Error);
}

TEST_F(View_Page, CovarianceAxesAndGroundTruth) {
  view::Scene scene(graph, types);
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(3, 3);
  c(0, 0) = 4.0;
  c(1, 1) = 1.0;
  c(2, 2) = 0.1;
  scene.addCovariance(1, c);
  scene.setGroundTruth({{0, Eigen::Vector3d(0.1, 0, 0)}}, {{0, 0.1}});
  const std::string page = scene.html();
  // Standard deviations 1 and 2 along y and x (ascending eigenvalues), vertex index 1.
  const auto at = page.find("\"covariances\":[{\"v\":1,\"axes\":[");
  ASSERT_NE(at, std::string::npos);
  std::istringstream in(page.substr(page.find('[', at + 20) + 1));
  std::vector<double> axes(4);
  char comma;
  in >> axes[0] >> comma >> axes[1] >> comma >> axes[2] >> comma >> axes[3];
  EXPECT_NEAR(std::abs(axes[1]), 1.0, 1e-9);
  EXPECT_NEAR(std::abs(axes[2]), 2.0, 1e-9);
  const auto ape = field<float>(page, "ape");
  ASSERT_EQ(ape.size(), 5u);
  EXPECT_FLOAT_EQ(ape[0], 0.1f);
  EXPECT_TRUE(std::isnan(ape[1]));
}

TEST_F(View_Page, UnknownVertexTypeIsDrawnGenericAndSaidInThePanel) {
  types.registerVertex<VertexOdd>("ODD_VERTEX");
  auto v = std::make_unique<VertexOdd>();
  v->setId(20);
  graph.addVertex(std::move(v));
  view::Scene scene(graph, types);
  const std::string page = scene.html();
  EXPECT_NE(page.find("unknown vertex type ODD_VERTEX (1): drawn as generic"), std::string::npos);
  EXPECT_NE(page.find("\"vertexTagKinds\":[0,1,2]"), std::string::npos);
}

TEST_F(View_Page, NonFiniteEstimatesAreRefusedNamingTheVertices) {
  const double bad[3] = {std::nan(""), 0, 0};
  graph.vertex(2)->setEstimateData(bad);
  view::Scene scene(graph, types);
  const fs::path out = fs::temp_directory_path() / "graphslam_view_nan.html";
  fs::remove(out);
  try {
    scene.writePage(out.string());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not finite (NaN or infinite): 2"), std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(out));
}

TEST(View_Scene, EmptyGraphAndMissingFolderAreRefused) {
  TypeRegistry types;
  Graph empty;
  EXPECT_THROW(view::Scene(empty, types), InputError);
  Graph g;
  types_slam2d::registerTypes(types);
  auto v = std::make_unique<types_slam2d::VertexSE2>();
  v->setId(0);
  g.addVertex(std::move(v));
  view::Scene scene(g, types);
  const fs::path out = fs::temp_directory_path() / "graphslam_no_such_folder" / "page.html";
  EXPECT_THROW(scene.writePage(out.string()), Error);
  EXPECT_FALSE(fs::exists(out.parent_path()));
}

TEST(View_Scene, ThreeDimensionalGraph) {
  TypeRegistry types;
  types_slam3d::registerTypes(types);
  Graph g;
  for (int i = 0; i < 2; ++i) {
    auto v = std::make_unique<types_slam3d::VertexSE3>();
    v->setId(i);
    const double x[7] = {1.0 * i, 2, 3, 0, 0, 0, 1};
    v->setEstimateData(x);
    g.addVertex(std::move(v));
  }
  view::Scene scene(g, types);
  const std::string page = scene.html();
  EXPECT_NE(page.find("\"dim\":3"), std::string::npos);
  const auto pos = field<float>(page, "pos");
  EXPECT_EQ(pos, (std::vector<float>{0, 2, 3, 1, 2, 3}));
}

TEST(View_Scene, OdometryJoinsPosesNextInIdOrderAcrossLandmarkIds) {
  // One counter for poses and landmarks (as dlr.g2o, victoria_park.g2o): poses 0, 2, 3,
  // landmark 1 between them.
  TypeRegistry types;
  types_slam2d::registerTypes(types);
  Graph g;
  for (int id : {0, 2, 3}) {
    auto v = std::make_unique<types_slam2d::VertexSE2>();
    v->setId(id);
    g.addVertex(std::move(v));
  }
  auto l = std::make_unique<types_slam2d::VertexXY>();
  l->setId(1);
  g.addVertex(std::move(l));
  for (std::vector<VertexId> ids : {std::vector<VertexId>{0, 2}, {2, 3}, {0, 3}}) {
    auto e = std::make_unique<types_slam2d::EdgeSE2>();
    e->setVertexIds(ids);
    g.addEdge(std::move(e));
  }
  view::Scene scene(g, types);
  EXPECT_EQ(field<std::uint8_t>(scene.html(), "ekind"), (std::vector<std::uint8_t>{0, 0, 1}));
}
