// SPDX-License-Identifier: MIT
#include "input.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "cli_common.h"
#include "graphslam/core/error.h"
#include "graphslam/core/io_g2o.h"
#include "graphslam/formats/text_format.h"
#include "graphslam/init/chordal3d.h"
#include "graphslam/init/initialization.h"

namespace graphslam::apps {

namespace {
std::string joinDiagnostics(const std::vector<io::Diagnostic>& diagnostics) {
  std::string all;
  for (const auto& d : diagnostics) all += (all.empty() ? "" : "\n") + d.str();
  return all;
}

/// A TORO or iSAM file: translated to .g2o text (line for line) and read from it.
io::LoadResult loadTranslated(const std::string& path, formats::TextFormat format,
                              const TypeRegistry& types, const io::LoadOptions& options,
                              LoadedInput& in) {
  const formats::Translation t = formats::translate(formats::readText(path), path, format);
  if (!t.ok()) throw InputError(joinDiagnostics(t.diagnostics));
  in.description = std::string(formats::displayName(format)) +
                   " graph, read as .g2o: " + std::to_string(t.vertices) + " vertex lines, " +
                   std::to_string(t.edges) + " edge lines";
  if (format == formats::TextFormat::kIsam) {
    in.notes.push_back(
        "iSAM square-root information R read as information R^T R" +
        std::string(t.landmark_id_offset == 0
                        ? ""
                        : "; landmark ids collide with pose ids: landmark l is vertex l + " +
                              std::to_string(t.landmark_id_offset)));
  }
  std::istringstream text(t.g2o);
  return io::readG2o(text, path, types, options);
}

bool hasExtension(const std::string& path, const std::string& ext) {
  if (path.size() < ext.size()) return false;
  return std::equal(ext.rbegin(), ext.rend(), path.rbegin(), [](char a, char b) {
    return std::tolower(static_cast<unsigned char>(a)) ==
           std::tolower(static_cast<unsigned char>(b));
  });
}
}  // namespace

homework::PointObservationModel parseNpzModel(const std::string& text) {
  using homework::PointObservationModel;
  for (auto m : {PointObservationModel::kAuto, PointObservationModel::kLinear,
                 PointObservationModel::kBearingRange}) {
    if (text == homework::toString(m)) return m;
  }
  throw UsageError("--npz-model must be auto, linear or bearing-range, not '" + text + "'");
}

InformationRepair parseInformationRepair(const std::string& text) {
  if (text == "refuse") return InformationRepair::kRefuse;
  if (text == "nearest-pd") return InformationRepair::kNearestPd;
  if (text == "isotropic") return InformationRepair::kIsotropic;
  throw UsageError("--information must be refuse, nearest-pd or isotropic, not '" + text + "'");
}

formats::TextFormat parseTextFormat(const std::string& text) {
  for (auto f :
       {formats::TextFormat::kG2o, formats::TextFormat::kToro, formats::TextFormat::kIsam}) {
    if (text == formats::toString(f)) return f;
  }
  throw UsageError("the input format must be auto, g2o, toro or isam, not '" + text + "'");
}

void checkInitChoice(const std::string& init) {
  if (init != "auto" && init != "global" && init != "none") {
    throw UsageError("--init must be auto, none or global, not '" + init + "'");
  }
}

namespace {
void reportInitialization(const char* kind, const init::InitializationReport& r) {
  if (!r.message.empty()) {
    std::cout << "initialisation: " << r.message << "\n";
  } else {
    std::printf("initialisation: %s, %zu poses and %zu landmarks placed in %.4f s\n", kind, r.poses,
                r.landmarks, r.seconds);
  }
}
}  // namespace

void applyInitialGuess(const LoadedInput& in, Graph& graph, std::string init,
                       const SolverRegistry& solvers) {
  checkInitChoice(init);
  if (init == "auto") {
    init = in.keep_initial_guess ? "none" : "global";
    if (in.keep_initial_guess) {
      std::cout << "initialisation: none (keeping the file's initial guess; --init global "
                   "applies to SE(2) and SE(3) pose graphs)\n";
    }
  }
  if (init != "global") {
    if (in.created_vertices > 0) {
      std::cout << "initialisation: none: the " << in.created_vertices
                << " vertices created from edges keep their default estimates\n";
    }
    return;
  }
  // The initial guess's two linear systems get the default solver's choice of ordering
  // and backend (large graphs need nested dissection and a supernodal factorisation).
  const auto init_solver = solvers.create("auto");
  const auto r2 = init::initializeGlobal(graph, init_solver.get());
  const auto r3 = init::initializeChordal3d(graph, init_solver.get());
  if (r2.poses > 0 || (!r2.message.empty() && r3.poses == 0 && r3.message.empty())) {
    reportInitialization("global", r2);
  }
  if (r3.poses > 0 || (!r3.message.empty() && r2.poses == 0 && r2.message.empty())) {
    reportInitialization("global 3D (chordal)", r3);
  }
  if (r2.poses == 0 && r3.poses == 0 && !r2.message.empty() && !r3.message.empty()) {
    std::cout << "initialisation: no EDGE_SE2 or EDGE_SE3:QUAT in the graph: nothing to "
                 "initialise\n";
  }
  std::fflush(stdout);
}

LoadedInput loadInput(const std::string& path, const TypeRegistry& types,
                      const InputOptions& options) {
  LoadedInput in;
  in.path = path;
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(path + ": is a folder, not a file");
  if (hasExtension(path, ".npz")) {
    homework::CourseworkNpzOptions o;
    o.model = options.npz_model;
    auto p = homework::loadCourseworkNpz(path, o);
    in.format = "npz";
    in.graph = std::move(p.graph);
    in.ground_truth = std::move(p.ground_truth);
    in.keep_initial_guess = true;
    in.description = "CMU 16-833 homework file, " + std::string(toString(p.model)) +
                     " observations: " + std::to_string(p.num_poses) + " poses, " +
                     std::to_string(p.num_landmarks) + " landmarks, " +
                     std::to_string(p.num_odometry) + " odometry, " +
                     std::to_string(p.num_observations) + " observations";
    in.notes.push_back("observation model " + std::string(toString(p.model)) + ": " +
                       p.model_reason);
    in.notes.push_back(p.model == homework::PointObservationModel::kLinear
                           ? "initial guess: all zero (the system is linear)"
                           : "initial guess: odometry summed from (0, 0), each landmark from "
                             "its first observation (the homework's init_states)");
    in.notes.insert(in.notes.end(), p.notes.begin(), p.notes.end());
    return in;
  }
  io::LoadOptions load_options;
  load_options.threads = options.threads;
  load_options.information = options.information;
  load_options.create_missing_vertices = options.create_missing_vertices;
  const formats::TextFormat text_format = options.text_format == "auto"
                                              ? formats::detectFileFormat(path)
                                              : parseTextFormat(options.text_format);
  io::LoadResult loaded;
  if (text_format == formats::TextFormat::kG2o) {
    loaded = io::loadG2o(path, types, load_options);
    in.description = ".g2o graph";
  } else {
    loaded = loadTranslated(path, text_format, types, load_options, in);
  }
  if (!loaded.ok()) throw InputError(joinDiagnostics(loaded.diagnostics));
  in.format = formats::toString(text_format);
  in.graph = std::move(loaded.graph);
  in.edge_lines = std::move(loaded.edge_lines);
  if (loaded.repaired_information > 0) {
    in.notes.push_back(
        std::to_string(loaded.repaired_information) + " of " + std::to_string(in.graph.numEdges()) +
        " information matrices were not positive definite and were repaired (" +
        (options.information == InformationRepair::kIsotropic ? "isotropic" : "nearest-pd") + ")");
  }
  in.created_vertices = loaded.created_vertices;
  if (in.created_vertices > 0) in.notes.push_back(createdVerticesNote(in));
  return in;
}

std::string createdVerticesNote(const LoadedInput& in) {
  if (in.created_vertices == 0) return {};
  const bool all = in.created_vertices == in.graph.numVertices();
  return "created " + std::to_string(in.created_vertices) +
         (in.created_vertices == 1 ? " vertex" : " vertices") + " from edges (" +
         (all ? "the file has no vertex lines" : "no line of the file defines them") +
         "; default estimates until initialised)";
}

void initializeCreatedVertices(const LoadedInput& in, Graph& graph, const SolverRegistry& solvers) {
  if (in.created_vertices > 0) applyInitialGuess(in, graph, "global", solvers);
}

}  // namespace graphslam::apps
