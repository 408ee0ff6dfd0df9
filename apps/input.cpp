// SPDX-License-Identifier: MIT
#include "input.h"

#include <cstdio>
#include <iostream>

#include "graphslam/init/initial_guess.h"
#include "graphslam/support/error.h"

namespace graphslam::apps {

InformationRepair parseInformationRepair(const std::string& text) {
  if (text == "refuse") return InformationRepair::kRefuse;
  if (text == "nearest-pd") return InformationRepair::kNearestPd;
  if (text == "isotropic") return InformationRepair::kIsotropic;
  throw UsageError("--information must be refuse, nearest-pd or isotropic, not '" + text + "'");
}

void checkGraphFormat(const std::string& format, const Registries& reg) {
  std::string known = "auto";
  for (const auto* f : reg.formats.formats<io::GraphFile>()) {
    if (!f->read) continue;
    if (f->name == format) return;
    known += ", " + f->name;
  }
  if (format == "auto") return;
  throw UsageError("--from must be " + known + ", not '" + format + "'");
}

void checkInitChoice(const std::string& init) {
  if (init != "auto" && init != "global" && init != "none") {
    throw UsageError("--init must be auto, none or global, not '" + init + "'");
  }
}

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
  for (const std::string& line : init::initializeGraph(graph, solvers).lines) {
    std::cout << "initialisation: " << line << "\n";
  }
  std::cout.flush();
}

LoadedInput loadInput(const std::string& path, const Registries& reg, const InputOptions& options) {
  io::ReadContext context;
  context.types = &reg.types;
  context.load.threads = options.threads;
  context.load.information = options.information;
  context.load.create_missing_vertices = options.create_missing_vertices;
  context.choices = options.choices;
  context.choices["npz-model"] = options.npz_model;
  return io::readGraph(path, reg.formats, context, options.format);
}

void initializeCreatedVertices(const LoadedInput& in, Graph& graph, const SolverRegistry& solvers) {
  if (in.created_vertices > 0) applyInitialGuess(in, graph, "global", solvers);
}

}  // namespace graphslam::apps
