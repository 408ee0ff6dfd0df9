// SPDX-License-Identifier: MIT
// graphslam view: one self-contained web page to explore a graph (the view module).
#include <chrono>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "cli_common.h"
#include "input.h"
#include "output_set.h"
#include "view_output.h"

namespace graphslam::apps {

namespace {

constexpr const char* kViewUsage =
    "usage: graphslam view IN [-o PAGE.html] [--title TEXT] [--covariance IDS] [--from FORMAT]\n"
    "                          [--plugin LIB]...\n"
    "Writes one web page (HTML with its data, script and style inside: it opens from disk,\n"
    "offline) to explore the graph IN as its file has it: 2D graphs pan and zoom, 3D graphs\n"
    "orbit; vertices by type, edges by kind (odometry, loop closure, landmark, prior) with\n"
    "switches, coloured by their chi2; hover or click an element for its id, tag, error, chi2\n"
    "and file line. Without -o the page is IN's name with .html, in the current folder.\n"
    "optimize, incremental, eval and drivebot write pages of their results with --view.";

}  // namespace

int cmdView(const std::vector<std::string>& args) {
  std::string input, output, title, covariance, from = "auto", information = "refuse";
  std::vector<std::string> plugins;
  po::options_description desc("options");
  desc.add_options()("help,h", "show this help")("input", po::value(&input),
                                                 "the graph (.g2o, TORO, iSAM, .npz, matrix)")(
      "output,o", po::value(&output), "the page (default: IN's name with .html)")(
      "title", po::value(&title), "the page's title (default: IN's file name)")(
      "covariance", po::value(&covariance),
      "draw the 3-sigma marginal covariance of these vertices (ids separated by commas), "
      "computed at the file's estimate")(
      "from", po::value(&from)->default_value("auto"),
      "input format: auto (from its name and content) or a graph format's name")(
      "information", po::value(&information)->default_value("refuse"),
      "information matrices that are not positive definite: refuse, nearest-pd or isotropic")(
      "plugin", po::value(&plugins)->composing(), "also load this plugin (repeatable)");
  po::positional_options_description pos;
  pos.add("input", 1);
  const auto vm = parse(args, desc, &pos);
  if (vm.count("help")) {
    printHelp(kViewUsage, desc);
    return kExitOk;
  }
  if (input.empty()) throw UsageError("view needs IN, the graph to draw");
  if (output.empty()) {
    if (input == "-") throw UsageError("a graph read from standard input needs -o PAGE.html");
    output = std::filesystem::path(input).filename().replace_extension(".html").string();
  }
  const std::vector<VertexId> ids =
      covariance.empty() ? std::vector<VertexId>{} : parseIdList(covariance, "covariance");
  Registries reg;
  loadRegistries(reg, plugins);
  checkGraphFormat(from, reg);
  OutputSet outputs({output}, {input});
  InputOptions options;
  options.format = from;
  options.information = parseInformationRepair(information);
  LoadedInput in = loadInput(input, reg, options);
  std::cout << input << ": " << in.description << ", " << in.graph.numVertices() << " vertices, "
            << in.graph.numEdges() << " edges\n";
  initializeCreatedVertices(in, in.graph, reg.solvers);
  view::Options view_options;
  view_options.title = title.empty() ? std::filesystem::path(input).filename().string() : title;
  view::Scene scene(in.graph, reg.types, view_options);
  scene.setSourceLines(in.path, in.vertex_lines, in.edge_lines);
  scene.addSummary("estimate", "as the file has it (not optimised)");
  scene.addSummary("format", in.description);
  for (const auto& note : in.notes) scene.addSummary("note", note);
  addCovariances(scene, in.graph, reg, ids, "covariance");
  return outputs.writeAll([&] {
    const auto t0 = std::chrono::steady_clock::now();
    scene.writePage(outputs.staged(output));
    const std::chrono::duration<double> took = std::chrono::steady_clock::now() - t0;
    outputs.commit();
    std::error_code ec;  // no size for a device or a FIFO
    const auto size = std::filesystem::file_size(output, ec);
    std::cout << "wrote " << output;
    if (!ec) std::cout << " (" << size / 1024 << " KiB)";
    std::cout << " in " << took.count() << " s\n";
    return kExitOk;
  });
}

}  // namespace graphslam::apps
