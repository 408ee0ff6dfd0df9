// SPDX-License-Identifier: MIT
#include "factor_graph_dot.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <vector>

#include "cli_common.h"
#include "graphslam/support/error.h"
#include "graphslam/support/file_util.h"
#include "plotting.h"

namespace graphslam::apps {

namespace {

/// Colours of edge types, in order of first appearance (ColorBrewer Set1 and Dark2).
constexpr const char* kColors[] = {"#e41a1c", "#377eb8", "#4daf4a", "#984ea3", "#ff7f00",
                                   "#a65628", "#f781bf", "#1b9e77", "#d95f02", "#7570b3"};

std::string tagOf(const TypeRegistry& types, const Vertex& v) {
  const std::string* t = types.tagOf(v);
  return t ? *t : "vertex";
}

std::string tagOf(const TypeRegistry& types, const Edge& e) {
  const std::string* t = types.tagOf(e);
  return t ? *t : "edge";
}

/// "VERTEX_VEHICLE" -> "vehicle", "VERTEX_SE2" -> "se2".
std::string shortVertexTag(std::string tag) {
  if (tag.rfind("VERTEX_", 0) == 0) tag = tag.substr(7);
  for (char& c : tag) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return tag;
}

std::string htmlEscaped(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '<') {
      out += "&lt;";
    } else if (c == '>') {
      out += "&gt;";
    } else if (c == '&') {
      out += "&amp;";
    } else {
      out += c;
    }
  }
  return out;
}

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string extensionOf(const std::string& path) {
  const auto dot = path.find_last_of('.');
  const auto slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
  return path.substr(dot + 1);
}

}  // namespace

void writeFactorGraphDot(std::ostream& out, const Graph& graph, const TypeRegistry& types,
                         const std::string& title) {
  // A spring layout (neato): chains stay chains and loops stay loops. The legend of the
  // factor types is part of the title (an HTML label): neato ignores clusters.
  out << "graph factor_graph {\n  layout=neato; overlap=false; sep=\"+4\"; fontsize=12;\n"
      << "  node [fontsize=9, fontname=\"Helvetica\"];\n  edge [color=\"#666666\"];\n";
  bool any_fixed = false;
  for (const auto& [id, v] : graph.vertices()) {
    any_fixed = any_fixed || v->fixed();
    out << "  v" << id << " [shape=" << (v->fixed() ? "doublecircle" : "circle")
        << ", margin=0.02, width=0.45, style=filled, fillcolor="
        << (v->fixed() ? "\"#bbbbbb\"" : "\"#ffffff\"")
        << ", label=" << quoted(std::to_string(id) + "\n" + shortVertexTag(tagOf(types, *v)))
        << "];\n";
  }
  std::vector<std::pair<std::string, std::string>> color;  // edge tag, colour; first seen first
  std::size_t k = 0;
  for (const auto& e : graph.edges()) {
    const std::string tag = tagOf(types, *e);
    auto it =
        std::find_if(color.begin(), color.end(), [&](const auto& c) { return c.first == tag; });
    if (it == color.end()) {
      color.emplace_back(tag, kColors[color.size() % (sizeof kColors / sizeof *kColors)]);
      it = color.end() - 1;
    }
    out << "  f" << k << " [shape=square, label=\"\", width=0.12, height=0.12, style=filled, "
        << "color=" << quoted(it->second) << "];\n";
    for (std::size_t s = 0; s < e->numVertices(); ++s) {
      out << "  f" << k << " -- v" << e->vertexId(s) << ";\n";
    }
    ++k;
  }
  out << "  labelloc=t; label=<" << htmlEscaped(title)
      << "<br/><font point-size=\"10\">circles: variables"
      << (any_fixed ? " (grey double circle: fixed)" : " (none fixed)") << "; squares: factors";
  for (const auto& [tag, c] : color) {
    out << "&nbsp;&nbsp;<font color=\"" << c << "\">&#9632; " << htmlEscaped(tag) << "</font>";
  }
  out << "</font>>;\n}\n";
}

void plotFactorGraph(const std::string& out, const Graph& graph, const TypeRegistry& types,
                     const FactorGraphPlotOptions& options) {
  if (graph.numVertices() == 0)
    throw UsageError("the graph has no vertices: no factor graph to draw");
  if (graph.numVertices() > options.max_vertices) {
    throw UsageError(
        "--plot-graph draws graphs of at most " + std::to_string(options.max_vertices) +
        " vertices (--plot-graph-max), this one has " + std::to_string(graph.numVertices()) +
        ": draw a smaller part, e.g. the first steps of a run (drivebot --max-steps N)");
  }
  const std::string ext = extensionOf(out);
  if (ext != "dot" && ext != "png" && ext != "svg" && ext != "pdf") {
    throw UsageError("--plot-graph writes FILE.dot, FILE.png, FILE.svg or FILE.pdf, not '" + out +
                     "'");
  }
  const std::string dot_file = ext == "dot" ? out : out + ".dot";
  support::writeFileAtomically(
      dot_file, [&](std::ostream& s) { writeFactorGraphDot(s, graph, types, options.title); });
  if (ext == "dot") {
    std::printf("wrote %s (draw it with: dot -Tpng %s -o FILE.png)\n", out.c_str(), out.c_str());
    return;
  }
  if (runCommand({"dot", "-V"}, true) != 0) {
    throw Error("Graphviz's dot was not found, so " + out + " was not drawn; the graph is in " +
                dot_file + " (install Graphviz with 'apt-get install graphviz' and run: dot -T" +
                ext + " " + dot_file + " -o " + out + ")");
  }
  if (runCommand({"dot", "-T" + ext, dot_file, "-o", out}, false) != 0) {
    throw Error("Graphviz's dot failed to draw " + out + " from " + dot_file);
  }
  std::printf("wrote %s (Graphviz source: %s)\n", out.c_str(), dot_file.c_str());
}

}  // namespace graphslam::apps
