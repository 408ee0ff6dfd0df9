// SPDX-License-Identifier: MIT
// graphslam add-outliers: random wrong loop closures appended to a 2D pose graph.
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "cli_common.h"
#include "graphslam/io/g2o.h"
#include "graphslam/simulation/wrong_loop_closures.h"
#include "graphslam/support/file_util.h"
#include "input.h"
#include "output_set.h"

namespace graphslam::apps {

namespace {

constexpr const char* kAddOutliersUsage =
    "usage: graphslam add-outliers IN.g2o -o OUT.g2o (--fraction F | --count N) [--seed S]\n"
    "                              [--list FILE] [--translation-range R] [--plugin LIB]...\n"
    "Appends random wrong loop closures to a 2D pose graph: EDGE_SE2 between two random poses\n"
    "whose ids differ by more than one and that no edge joins yet, with a random measurement\n"
    "(each translation component uniform in [-R, R], R by default half the larger side of the\n"
    "poses' bounding box; angle uniform) and the information of a random existing loop\n"
    "closure. --fraction counts against the graph's loop closures (EDGE_SE2 between ids that\n"
    "are not consecutive): 0.1 adds one wrong closure per ten right ones. OUT holds the\n"
    "input's vertices and edges with the wrong ones last; --list writes one line per wrong\n"
    "edge: its line in OUT and its two vertex ids. The same seed gives the same edges.";

struct AddOutliersOptions {
  std::string input, output, list;
  std::vector<std::string> plugins;
  simulation::WrongLoopClosureOptions wrong;
};

/// Parses and checks the options; false after --help.
bool parseAddOutliers(const std::vector<std::string>& args, AddOutliersOptions& o) {
  simulation::WrongLoopClosureOptions& w = o.wrong;
  po::options_description desc("options");
  desc.add_options()("help,h", "show this help")("input", po::value(&o.input), "input .g2o file")(
      "output,o", po::value(&o.output), "write the corrupted graph here (atomically)")(
      "fraction", po::value(&w.fraction),
      "wrong closures per right loop closure of the input (e.g. 0.1 or 0.2)")(
      "count", po::value(&w.count), "exactly this many wrong closures")(
      "seed", po::value(&w.seed)->default_value(w.seed), "random seed")(
      "list", po::value(&o.list), "write the wrong edges' lines in OUT and vertex ids here")(
      "translation-range", doubleValue(&w.translation_range, w.translation_range),
      "half-width (m) of the measurements' translation box; 0: from the poses' extent")(
      "plugin", po::value(&o.plugins)->composing(), "load types from this shared library");
  po::positional_options_description pos;
  pos.add("input", 1);
  const auto vm = parse(args, desc, &pos);
  if (vm.count("help")) {
    printHelp(kAddOutliersUsage, desc);
    return false;
  }
  if (o.input.empty()) throw UsageError("add-outliers needs an input file IN.g2o");
  if (o.output.empty()) throw UsageError("add-outliers needs -o OUT.g2o");
  if (o.output == o.input) throw UsageError("-o names the input file, " + o.input);
  if (vm.count("fraction") == vm.count("count"))
    throw UsageError("give exactly one of --fraction F and --count N");
  if (vm.count("fraction") && !(w.fraction >= 0 && std::isfinite(w.fraction)))
    throw UsageError("--fraction must be a finite number >= 0");
  if (vm.count("count") && w.count < 0) throw UsageError("--count must be at least 0");
  if (!(w.translation_range >= 0 && std::isfinite(w.translation_range)))
    throw UsageError("--translation-range must be a finite number >= 0");
  if (!o.list.empty() && (o.list == o.output || o.list == o.input))
    throw UsageError("--list names the input or output file, " + o.list);
  return true;
}

/// Adds the wrong loop closures of `o` to `graph` and writes the graph and the --list file
/// (staged in `outputs`, put in place together).
int addOutliers(const AddOutliersOptions& o, const Registries& reg, Graph& graph,
                OutputSet& outputs) {
  const auto added = simulation::addWrongLoopClosures(graph, o.wrong);
  io::saveG2o(outputs.staged(o.output), graph, reg.types);
  // writeG2o's layout: vertices, FIX lines, then edges in graph order.
  std::size_t fixed = 0;
  for (const auto& [id, v] : graph.vertices()) fixed += v->fixed() ? 1 : 0;
  const std::size_t first_edge_line = graph.numVertices() + fixed + 1;
  std::cout << "wrote " << o.output << ": " << added.edge_indices.size()
            << " wrong loop closures added to " << added.loop_closures << " loop closures ("
            << graph.numEdges() << " edges in all)\n";
  if (added.edge_indices.size() < added.requested) {
    std::cerr << "warning: only " << added.edge_indices.size() << " of " << added.requested
              << " wrong loop closures found a free pose pair\n";
  }
  if (!o.list.empty()) {
    support::writeFileAtomically(outputs.staged(o.list), [&](std::ostream& out) {
      out << "# line id_i id_j (wrong loop closures in " << o.output << ")\n";
      for (std::size_t k : added.edge_indices) {
        const Edge& e = *graph.edges()[k];
        out << first_edge_line + k << ' ' << e.vertexId(0) << ' ' << e.vertexId(1) << '\n';
      }
    });
  }
  outputs.commit();
  if (!o.list.empty()) std::cout << "wrote " << o.list << "\n";
  return kExitOk;
}

}  // namespace

int cmdAddOutliers(const std::vector<std::string>& args) {
  AddOutliersOptions o;
  if (!parseAddOutliers(args, o)) return kExitOk;
  Registries reg;
  loadRegistries(reg, o.plugins);
  // Both outputs checked before the work and put in place together.
  OutputSet outputs({o.output, o.list}, {o.input});
  LoadedInput in = loadInput(o.input, reg);
  if (in.format == "npz")
    throw UsageError("add-outliers reads .g2o, TORO or iSAM graphs, not " + o.input);
  return outputs.writeAll([&] { return addOutliers(o, reg, in.graph, outputs); });
}

}  // namespace graphslam::apps
