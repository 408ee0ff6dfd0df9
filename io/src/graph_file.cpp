// SPDX-License-Identifier: MIT
#include "graphslam/io/graph_file.h"

#include <sys/stat.h>

#include "graphslam/io/trajectory.h"
#include "graphslam/support/error.h"
#include "graphslam/support/file_util.h"

namespace graphslam::io {

namespace {

/// A name that says "trajectory" (.tum, .kitti) and that no graph format claims.
void refuseTrajectoryName(const std::string& name, const FormatRegistry& formats) {
  for (const auto* g : formats.formats<GraphFile>()) {
    if (FormatRegistry::hasExtension(name, g->extensions)) return;
  }
  for (const auto* t : formats.formats<Trajectory>()) {
    if (FormatRegistry::hasExtension(name, t->extensions) && t->extensions.front() != ".txt" &&
        !FormatRegistry::hasExtension(name, {".txt"})) {
      throw InputError(name + " is named as a " + t->name +
                       " trajectory, not a graph (give --from FORMAT to read it as one of the "
                       "graph formats)");
    }
  }
}

const Format<GraphFile>& formatToRead(Source& source, const FormatRegistry& formats,
                                      const std::string& format) {
  if (format == "auto") {
    refuseTrajectoryName(source.name(), formats);
    return formats.detect<GraphFile>(source, "g2o");
  }
  const Format<GraphFile>* f = formats.find<GraphFile>(format);
  if (!f || !f->read) {
    std::string known;
    for (const auto* g : formats.formats<GraphFile>()) {
      if (g->read) known += (known.empty() ? "" : ", ") + g->name;
    }
    throw InputError("unknown graph format '" + format + "' (readable: " + known + ")");
  }
  return *f;
}

}  // namespace

GraphFile readGraph(const std::string& path, const FormatRegistry& formats,
                    const ReadContext& context, const std::string& format) {
  Source source = Source::open(path);
  return readGraph(source, formats, context, format);
}

GraphFile readGraph(Source& source, const FormatRegistry& formats, const ReadContext& context,
                    const std::string& format) {
  const Format<GraphFile>& f = formatToRead(source, formats, format);
  ReadContext ctx = context;
  if (format != "auto") ctx.choices.emplace("from", format);
  GraphFile out = f.read(source, ctx);
  out.path = source.name();
  out.format = f.name;
  if (out.graph.numVertices() == 0 && out.graph.numEdges() == 0) {
    throw InputError(source.name() + ": the graph is empty (no vertex and no edge)");
  }
  if (out.repaired_information > 0) {
    out.notes.push_back(
        std::to_string(out.repaired_information) + " of " + std::to_string(out.graph.numEdges()) +
        " information matrices were not positive definite and were repaired (" +
        (context.load.information == InformationRepair::kIsotropic ? "isotropic" : "nearest-pd") +
        ")");
  }
  if (out.created_vertices > 0) out.notes.push_back(createdVerticesNote(out));
  return out;
}

void writeGraph(const std::string& path, const Graph& graph, const FormatRegistry& formats,
                const WriteContext& context, const std::string& format) {
  const Format<GraphFile>* f = nullptr;
  if (format == "auto") {
    f = formats.forOutput<GraphFile>(path);
    if (!f) {
      for (const auto* t : formats.formats<Trajectory>()) {
        if (FormatRegistry::hasExtension(path, t->extensions)) {
          throw InputError(path + " is named as a " + t->name +
                           " trajectory, not a graph: write a graph to a .g2o file (graphslam "
                           "convert writes trajectories)");
        }
      }
      f = formats.find<GraphFile>("g2o");
    }
  } else {
    f = formats.find<GraphFile>(format);
  }
  if (!f || !f->write) throw InputError("graph format '" + format + "' cannot be written");
  support::writeFileAtomically(path, [&](std::ostream& out) { f->write(graph, out, context); });
}

std::string createdVerticesNote(const GraphFile& in) {
  if (in.created_vertices == 0) return {};
  const bool all = in.created_vertices == in.graph.numVertices();
  return "created " + std::to_string(in.created_vertices) +
         (in.created_vertices == 1 ? " vertex" : " vertices") + " from edges (" +
         (all ? "the file has no vertex lines" : "no line of the file defines them") +
         "; default estimates until initialised)";
}

}  // namespace graphslam::io
