// SPDX-License-Identifier: MIT
// The graph formats of the io module: .g2o, TORO, iSAM, the CMU homework's .npz and the
// relative-pose matrix, each one registry entry (registerFormats, register.h).
#include "graph_formats.h"

#include <Eigen/Cholesky>
#include <cstdlib>
#include <sstream>

#include "graphslam/io/graph_file.h"
#include "graphslam/io/relative_poses.h"
#include "graphslam/io/text_tokens.h"
#include "graphslam/io/toro_isam.h"
#include "graphslam/io/trajectory.h"
#include "graphslam/support/error.h"
#include "line_translator.h"

namespace graphslam::io {

namespace {

/// The most a text format translated in memory (TORO, iSAM) or an archive read from a pipe
/// may hold: far beyond the largest public graph (290 MB at a million 2D poses).
constexpr std::size_t kMaxInMemoryBytes = std::size_t{4} << 30;

std::string joinDiagnostics(const std::vector<Diagnostic>& diagnostics) {
  std::string all;
  for (const auto& d : diagnostics) all += (all.empty() ? "" : "\n") + d.str();
  return all;
}

const TypeRegistry& typesOf(const ReadContext& context, const std::string& name) {
  if (!context.types) throw Error(name + ": reading a graph needs a type registry");
  return *context.types;
}

/// A LoadResult as a GraphFile; throws InputError with its diagnostics when it failed.
GraphFile fromLoadResult(LoadResult loaded, const std::string& name, const std::string& format) {
  if (!loaded.ok()) throw InputError(joinDiagnostics(loaded.diagnostics));
  GraphFile out;
  out.path = name;
  out.format = format;
  out.graph = std::move(loaded.graph);
  out.edge_lines = std::move(loaded.edge_lines);
  out.vertex_lines = std::move(loaded.vertex_lines);
  out.created_vertices = loaded.created_vertices;
  out.repaired_information = loaded.repaired_information;
  return out;
}

GraphFile readG2oFile(Source& source, const ReadContext& context) {
  GraphFile out = fromLoadResult(
      readG2o(source.stream(), source.name(), typesOf(context, source.name()), context.load),
      source.name(), "g2o");
  out.description = ".g2o graph";
  return out;
}

/// The first tag of `text` (comments and blank lines skipped), empty when there is none.
std::string_view firstTag(std::string_view text) {
  std::string_view first;
  detail::forEachLine(text, [&](int, const detail::Tokens& tokens) {
    if (tokens.empty()) return true;
    first = tokens[0];
    return false;
  });
  return first;
}

/// A first token that is a number: a matrix of numbers, not a file of tagged lines.
bool isNumber(std::string_view token) {
  if (token.empty()) return false;
  const std::string text(token);
  char* end = nullptr;
  (void)std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size();
}

bool isToroTag(std::string_view tag) {
  return tag == "VERTEX2" || tag == "VERTEX3" || tag == "VERTEX" || tag == "EDGE2" ||
         tag == "EDGE3" || tag == "EDGE";
}
bool isIsamOnlyTag(std::string_view tag) {
  return tag == "ODOMETRY" || tag == "LANDMARK" || tag == "Constraint2";
}

/// Which of TORO and iSAM a whole text is: a file with vertex lines is TORO, one with an
/// iSAM-only tag or starting with one is iSAM, EDGE3 lines alone are TORO (iSAM has no 3D
/// edges). EDGE2 (or EDGE) lines alone are both formats' with different information
/// layouts: refused unless the user said which (ReadContext::choices "from").
TextFormat toroOrIsam(std::string_view text, const std::string& name, const ReadContext& context) {
  if (const auto from = context.choices.find("from"); from != context.choices.end()) {
    if (from->second == "toro") return TextFormat::kToro;
    if (from->second == "isam") return TextFormat::kIsam;
  }
  bool vertices = false, isam = false, edge3 = false;
  detail::forEachLine(text, [&](int, const detail::Tokens& tokens) {
    if (tokens.empty()) return true;
    const std::string_view tag = tokens[0];
    vertices = vertices || tag == "VERTEX2" || tag == "VERTEX3" || tag == "VERTEX";
    isam = isam || isIsamOnlyTag(tag);
    edge3 = edge3 || tag == "EDGE3";
    return !(vertices || isam);
  });
  if (vertices) return TextFormat::kToro;
  if (isam) return TextFormat::kIsam;
  if (edge3) return TextFormat::kToro;
  throw InputError(name +
                   ": EDGE2 lines without vertex lines are both TORO's and iSAM's, whose "
                   "information layouts differ (TORO: xx xy yy tt xt yt; iSAM: the square root "
                   "R11 R12 R13 R22 R23 R33): say which with --from toro or --from isam");
}

GraphFile readTranslated(Source& source, const ReadContext& context, bool isam_entry) {
  const std::string text = source.readAll(kMaxInMemoryBytes);
  const std::string& name = source.name();
  TextFormat format = isam_entry ? TextFormat::kIsam : toroOrIsam(text, name, context);
  if (isam_entry && context.choices.count("from") == 0 && isToroTag(firstTag(text))) {
    format = toroOrIsam(text, name, context);
  }
  const Translation t = translate(text, name, format);
  if (!t.ok()) throw InputError(joinDiagnostics(t.diagnostics));
  std::istringstream g2o(t.g2o);
  GraphFile out = fromLoadResult(readG2o(g2o, name, typesOf(context, name), context.load), name,
                                 toString(format));
  out.description = std::string(displayName(format)) +
                    " graph, read as .g2o: " + std::to_string(t.vertices) + " vertex lines, " +
                    std::to_string(t.edges) + " edge lines";
  if (format == TextFormat::kIsam) {
    out.notes.push_back(
        "iSAM square-root information R read as information R^T R" +
        std::string(t.landmark_id_offset == 0
                        ? ""
                        : "; landmark ids collide with pose ids: landmark l is vertex l + " +
                              std::to_string(t.landmark_id_offset)));
  }
  return out;
}

/// The CMU homework's observation model choice ("npz-model": auto, linear, bearing-range).
PointObservationModel npzModel(const ReadContext& context) {
  const auto it = context.choices.find("npz-model");
  if (it == context.choices.end()) return PointObservationModel::kAuto;
  for (auto m : {PointObservationModel::kAuto, PointObservationModel::kLinear,
                 PointObservationModel::kBearingRange}) {
    if (it->second == toString(m)) return m;
  }
  throw InputError("the .npz observation model must be auto, linear or bearing-range, not '" +
                   it->second + "'");
}

GraphFile readNpzFile(Source& source, const ReadContext& context) {
  CourseworkNpzOptions options;
  options.model = npzModel(context);
  const NpzArchive archive =
      source.isRegularFile()
          ? NpzArchive(source.name())
          : NpzArchive::fromBytes(source.readAll(kMaxInMemoryBytes), source.name());
  CourseworkProblem p = loadCourseworkNpz(archive, options);
  GraphFile out;
  out.path = source.name();
  out.format = "npz";
  out.graph = std::move(p.graph);
  out.ground_truth = std::move(p.ground_truth);
  out.keep_initial_guess = true;
  out.description = "CMU 16-833 homework file, " + std::string(toString(p.model)) +
                    " observations: " + std::to_string(p.num_poses) + " poses, " +
                    std::to_string(p.num_landmarks) + " landmarks, " +
                    std::to_string(p.num_odometry) + " odometry, " +
                    std::to_string(p.num_observations) + " observations";
  out.notes.push_back("observation model " + std::string(toString(p.model)) + ": " +
                      p.model_reason);
  out.notes.push_back(p.model == PointObservationModel::kLinear
                          ? "initial guess: all zero (the system is linear)"
                          : "initial guess: odometry summed from (0, 0), each landmark from "
                            "its first observation (the homework's init_states)");
  out.notes.insert(out.notes.end(), p.notes.begin(), p.notes.end());
  return out;
}

/// The relative-pose matrix's options: "loop-closure" (yes: the last column closes the
/// loop to pose 0; no) and "information" (six numbers, the upper triangle).
RelativePoseGraphOptions matrixOptions(const ReadContext& context) {
  RelativePoseGraphOptions options;
  if (const auto it = context.choices.find("loop-closure"); it != context.choices.end()) {
    options.last_column_closes_loop = it->second != "no";
  }
  if (const auto it = context.choices.find("information"); it != context.choices.end()) {
    std::istringstream values(it->second);
    std::vector<double> v;
    for (double x; values >> x;) v.push_back(x);
    if (v.size() != 6) {
      throw InputError("the information takes 6 numbers (upper triangle of a 3x3 matrix)");
    }
    options.information << v[0], v[1], v[2], v[1], v[3], v[4], v[2], v[4], v[5];
    if (options.information.llt().info() != Eigen::Success) {
      throw InputError("the information is not positive definite");
    }
  }
  return options;
}

GraphFile readMatrixFile(Source& source, const ReadContext& context) {
  const RelativePoseGraphOptions options = matrixOptions(context);
  GraphFile out;
  out.path = source.name();
  out.format = "matrix";
  out.graph = poseGraphFromRelativePoses(readMatrix3xN(source.stream(), source.name()), options);
  out.description =
      "3xN relative-pose matrix: " + std::to_string(out.graph.numVertices()) + " poses, " +
      std::to_string(out.graph.numEdges()) + " edges" +
      (options.last_column_closes_loop ? " (last column as the loop closure to pose 0)" : "");
  return out;
}

}  // namespace

void registerGraphFormats(FormatRegistry& formats) {
  Format<GraphFile> g2o;
  g2o.name = "g2o";
  g2o.description = "g2o's text format: one vertex, edge, parameter or FIX per line";
  g2o.extensions = {".g2o"};
  g2o.sniff = [](std::string_view head) {
    const std::string_view tag = firstTag(head);
    return !tag.empty() && !isToroTag(tag) && !isIsamOnlyTag(tag) && !isNumber(tag);
  };
  g2o.read = readG2oFile;
  g2o.write = [](const Graph& graph, std::ostream& out, const WriteContext& context) {
    if (!context.types) throw Error("writing a .g2o file needs a type registry");
    writeG2o(out, graph, *context.types);
  };
  formats.add(std::move(g2o));

  Format<GraphFile> toro;
  toro.name = "toro";
  toro.description = "TORO 2D/3D (VERTEX2/EDGE2, VERTEX3/EDGE3), read as .g2o";
  toro.extensions = {".graph"};
  toro.sniff = [](std::string_view head) { return isToroTag(firstTag(head)); };
  toro.read = [](Source& source, const ReadContext& context) {
    return readTranslated(source, context, false);
  };
  formats.add(std::move(toro));

  Format<GraphFile> isam;
  isam.name = "isam";
  isam.description = "iSAM 2D (ODOMETRY/EDGE2, LANDMARK; square-root information), read as .g2o";
  isam.sniff = [](std::string_view head) { return isIsamOnlyTag(firstTag(head)); };
  isam.read = [](Source& source, const ReadContext& context) {
    return readTranslated(source, context, true);
  };
  formats.add(std::move(isam));

  Format<GraphFile> npz;
  npz.name = "npz";
  npz.description = "CMU 16-833 homework .npz (point robot, ground truth)";
  npz.extensions = {".npz"};
  npz.sniff = [](std::string_view head) { return head.substr(0, 4) == std::string_view("PK\3\4"); };
  npz.read = readNpzFile;
  formats.add(std::move(npz));

  Format<GraphFile> matrix;
  matrix.name = "matrix";
  matrix.description = "3xN relative SE(2) poses (the SE(2) homework), as a pose graph";
  matrix.sniff = [](std::string_view head) { return isNumber(firstTag(head)); };
  matrix.read = readMatrixFile;
  formats.add(std::move(matrix));
}

}  // namespace graphslam::io
