// SPDX-License-Identifier: MIT
// graphslam info: counts, components, fixed vertices and the sparsity picture of H.
#include <cstdio>
#include <filesystem>
#include <map>
#include <numeric>
#include <string>
#include <vector>

#include "cli_common.h"
#include "factor_graph_dot.h"
#include "graphslam/support/file_util.h"
#include "input.h"
#include "observability_check.h"
#include "output_set.h"
#include "plotting.h"

namespace graphslam::apps {

namespace {

/// --plot-hessian: the block pattern of H (columns of each vertex in `column`, `n` in all).
void plotHessian(const std::string& plot, const std::string& input, const Graph& graph,
                 const std::map<VertexId, std::pair<int, int>>& column, int n) {
  if (n == 0) throw UsageError(input + ": the graph has no vertices: no H to draw");
  const std::string data = plot + ".blocks.csv";
  const TemporaryFile remove_data{data};
  support::writeFileAtomically(data, [&](std::ostream& out) {
    out << "n," << n << "\nrow,col,rows,cols\n";
    auto block = [&](VertexId a, VertexId b) {
      const auto [ra, da] = column.at(a);
      const auto [rb, db] = column.at(b);
      out << ra << ',' << rb << ',' << da << ',' << db << '\n';
    };
    for (const auto& [id, v] : graph.vertices()) block(id, id);
    for (const auto& e : graph.edges()) {
      for (std::size_t s = 0; s < e->numVertices(); ++s) {
        for (std::size_t t = 0; t < e->numVertices(); ++t) {
          if (s != t) block(e->vertexId(s), e->vertexId(t));
        }
      }
    }
  });
  runPlotScript(
      "plot_sparsity.py",
      {data, plot, "Information matrix H of " + std::filesystem::path(input).filename().string()});
  std::printf("wrote %s\n", plot.c_str());
}

}  // namespace

int cmdInfo(const std::vector<std::string>& args) {
  std::string input, plot, plot_graph, information = "refuse";
  FactorGraphPlotOptions graph_plot;
  std::vector<std::string> plugins;
  po::options_description desc("options");
  desc.add_options()("help,h", "show this help")("input", po::value(&input),
                                                 "input .g2o file or CMU 16-833 homework .npz")(
      "plot-hessian", po::value(&plot), "write a PNG of the sparsity of the information matrix H")(
      "plot-graph", po::value(&plot_graph),
      "draw the factor graph: FILE.png|.svg|.pdf (Graphviz's dot; the source beside it as "
      "FILE.png.dot) or FILE.dot")(
      "plot-graph-max", po::value(&graph_plot.max_vertices)->default_value(graph_plot.max_vertices),
      "largest graph --plot-graph draws (vertices)")(
      "information", po::value(&information)->default_value("refuse"),
      "edges whose information is not positive definite: refuse, nearest-pd or isotropic")(
      "plugin", po::value(&plugins)->composing(),
      "load types from this shared library (repeatable)");
  po::positional_options_description pos;
  pos.add("input", 1);
  const auto vm = parse(args, desc, &pos);
  if (vm.count("help")) {
    printHelp(
        "usage: graphslam info IN.g2o|IN.npz [--plot-hessian FILE.png] [--plot-graph FILE.png]\n"
        "                      [--information MODE] [--plugin LIB]...\n"
        "Counts per type, connected components, fixed vertices, the vertices the edges do not\n"
        "determine (with the reason), the sparsity of H and a picture of the factor graph.",
        desc);
    return kExitOk;
  }
  if (input.empty()) throw UsageError("info needs an input file");
  // Checked before any work: neither picture may be the input or the other picture (each
  // is written in place by its own writer, atomically).
  const OutputSet checked({plot, plot_graph}, {input});
  Registries reg;
  loadRegistries(reg, plugins);
  InputOptions input_options;
  input_options.information = parseInformationRepair(information);
  LoadedInput in = loadInput(input, reg, input_options);
  const Graph& graph = in.graph;
  if (in.format != "g2o" || !in.notes.empty()) {
    std::printf("%s: %s\n", input.c_str(), in.description.c_str());
    for (const auto& note : in.notes) std::printf("  %s\n", note.c_str());
  }
  // Created vertices have no estimates: the check below needs them where optimize puts them.
  initializeCreatedVertices(in, in.graph, reg.solvers);
  std::map<std::string, std::size_t> counts;
  for (const auto& [id, v] : graph.vertices()) ++counts[*reg.types.tagOf(*v)];
  for (const auto& e : graph.edges()) ++counts[*reg.types.tagOf(*e)];
  std::printf("%s: %zu vertices, %zu edges\n", input.c_str(), graph.numVertices(),
              graph.numEdges());
  for (const auto& [tag, n] : counts) std::printf("  %-20s %zu\n", tag.c_str(), n);

  // Columns of H in id order, over all vertices (fixed ones included, as the picture of H).
  std::map<VertexId, std::pair<int, int>> column;  // id -> (first column, dimension)
  std::map<VertexId, std::size_t> index;
  int n = 0;
  for (const auto& [id, v] : graph.vertices()) {
    column[id] = {n, v->dimension()};
    index[id] = index.size();
    n += v->dimension();
  }
  std::vector<std::size_t> parent(graph.numVertices());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const auto& e : graph.edges()) {
    for (std::size_t s = 1; s < e->numVertices(); ++s) {
      parent[find(index[e->vertexId(s)])] = find(index[e->vertexId(0)]);
    }
  }
  std::map<std::size_t, std::vector<VertexId>> components;
  for (const auto& [id, i] : index) components[find(i)].push_back(id);
  std::printf("connected components: %zu\n", components.size());
  std::size_t shown = 0;
  for (const auto& [root, ids] : components) {
    if (++shown > 10) {
      std::printf("  ...\n");
      break;
    }
    std::printf("  %zu vertices, ids %d..%d\n", ids.size(), ids.front(), ids.back());
  }
  std::string fixed;
  std::size_t num_fixed = 0;
  for (const auto& [id, v] : graph.vertices()) {
    if (!v->fixed()) continue;
    if (++num_fixed <= 20) fixed += " " + std::to_string(id);
  }
  std::size_t priors = 0;
  for (const auto& e : graph.edges()) priors += e->numVertices() == 1 ? 1 : 0;
  std::printf("fixed vertices: %zu%s%s\n", num_fixed,
              num_fixed ? ":"
              : priors  ? " (unary edges anchor the graph)"
                        : " (the optimizer fixes the lowest id)",
              fixed.c_str());
  std::printf("information matrix H: %d x %d\n", n, n);
  printObservability(in, reg.types);

  if (!plot.empty()) plotHessian(plot, input, graph, column, n);
  if (!plot_graph.empty()) {
    graph_plot.title = "factor graph of " + std::filesystem::path(input).filename().string() +
                       ": " + std::to_string(graph.numVertices()) + " variables, " +
                       std::to_string(graph.numEdges()) + " factors";
    plotFactorGraph(plot_graph, graph, reg.types, graph_plot);
  }
  return kExitOk;
}

}  // namespace graphslam::apps
