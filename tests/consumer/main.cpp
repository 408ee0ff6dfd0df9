// SPDX-License-Identifier: MIT
// Builds a unit square of four SE(2) poses from a rough guess, optimises it and prints the final
// chi2: once with the types and solvers registered directly (registerTypes, registerSolvers),
// once with registries filled from the installed plugins (the graph read from .g2o text).
#include <graphslam/core/plugin.h>
#include <graphslam/io/g2o.h>
#include <graphslam/optimizer/optimizer.h>
#include <graphslam/solvers/register.h>
#include <graphslam/types_slam2d/edge_se2.h>
#include <graphslam/types_slam2d/register.h>
#include <graphslam/types_slam2d/vertex_se2.h>

#include <cstdio>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

/// The same square from the installed plugins: no module registered by this program.
int optimizeWithInstalledPlugins() {
  using namespace graphslam;
  const auto files = findPluginFiles({GRAPHSLAM_PLUGIN_DIR});
  if (files.empty()) {
    std::printf("consumer: no plugins in %s\n", GRAPHSLAM_PLUGIN_DIR);
    return 1;
  }
  // Declared first, destroyed last: the registries and graphs hold code of the plugins.
  std::vector<std::unique_ptr<Plugin>> plugins;
  std::set<std::string> modules;
  TypeRegistry types;
  SolverRegistry solvers;
  KernelRegistry kernels;
  PluginHost host;
  host.types = &types;
  host.solvers = &solvers;
  host.kernels = &kernels;
  host.modules = &modules;
  std::vector<std::string> with_own = files;
  with_own.push_back(CONSUMER_PLUGIN);  // built by graphslam_add_plugin()
  loadPlugins(with_own, host, plugins);
  if (types.find("EDGE_CONSUMER_PRIOR") == nullptr) {
    std::printf("consumer: the plugin built with graphslam_add_plugin did not register\n");
    return 1;
  }
  std::istringstream text(
      "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1.1 0.1 1.5\nVERTEX_SE2 2 0.9 1.1 3.2\n"
      "VERTEX_SE2 3 -0.1 0.9 4.6\n"
      "EDGE_SE2 0 1 1 0 1.5707963267948966 1 0 0 1 0 1\n"
      "EDGE_SE2 1 2 1 0 1.5707963267948966 1 0 0 1 0 1\n"
      "EDGE_SE2 2 3 1 0 1.5707963267948966 1 0 0 1 0 1\n"
      "EDGE_SE2 3 0 1 0 1.5707963267948966 1 0 0 1 0 1\n");
  auto loaded = io::readG2o(text, "square.g2o", types);
  if (!loaded.ok()) {
    std::printf("consumer: %s\n", loaded.diagnostics.at(0).str().c_str());
    return 1;
  }
  Summary s;
  {
    Optimizer optimizer(loaded.graph, solvers);
    s = optimizer.optimize();
  }
  std::printf("consumer (%zu installed plugins): %s, chi2 %.3e\n", plugins.size(),
              toString(s.status), s.final_chi2);
  return s.final_chi2 < 1e-12 ? 0 : 1;
}

}  // namespace

int main() {
  using namespace graphslam;
  using namespace graphslam::types_slam2d;
  SolverRegistry solvers;
  solvers::registerSolvers(solvers);
  Graph graph;
  const SE2 guess[4] = {SE2(0, 0, 0), SE2(1.1, 0.1, 1.5), SE2(0.9, 1.1, 3.2), SE2(-0.1, 0.9, 4.6)};
  for (int i = 0; i < 4; ++i) {
    auto v = std::make_unique<VertexSE2>();
    v->setId(i);
    v->setEstimate(guess[i]);
    graph.addVertex(std::move(v));
  }
  for (int i = 0; i < 4; ++i) {
    auto e = std::make_unique<EdgeSE2>();
    e->setVertexIds({i, (i + 1) % 4});
    e->setMeasurement(SE2(1, 0, 1.5707963267948966));
    graph.addEdge(std::move(e));
  }
  Optimizer optimizer(graph, solvers);
  const Summary s = optimizer.optimize();
  std::printf("consumer: %s, chi2 %.3e\n", toString(s.status), s.final_chi2);
  if (s.final_chi2 >= 1e-12) return 1;
  return optimizeWithInstalledPlugins();
}
