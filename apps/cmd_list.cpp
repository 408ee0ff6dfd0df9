// SPDX-License-Identifier: MIT
// graphslam list-types and list-solvers: what this build (and its plugins) registers.
#include <cstdio>
#include <string>
#include <vector>

#include "cli_common.h"
#include "graphslam/solvers/register.h"

namespace graphslam::apps {

namespace {

std::string parameterNote(int n) {
  return n > 0 ? "  parameters " + std::to_string(n) : std::string();
}

}  // namespace

int cmdListTypes(const std::vector<std::string>& args) {
  Registries reg;
  if (!parseListing(
          args,
          "usage: graphslam list-types [--plugin LIB]...\nLists the .g2o tags this build knows.",
          reg)) {
    return kExitOk;
  }
  for (const auto* e : reg.types.entries()) {
    if (e->kind == TypeRegistry::Kind::kVertex) {
      auto v = e->make_vertex();
      std::printf("%-28s vertex  dim %d  values %d%s  (%s)\n", e->tag.c_str(), v->dimension(),
                  v->estimateDataDimension(), parameterNote(v->parameterDataDimension()).c_str(),
                  e->origin.c_str());
    } else if (e->kind == TypeRegistry::Kind::kParameter) {
      auto p = e->make_parameter();
      std::printf("%-28s param   values %d  (%s)\n", e->tag.c_str(), p->dataDimension(),
                  e->origin.c_str());
    } else {
      auto ed = e->make_edge();
      const std::string refers =
          ed->numParameters() > 0 ? "  parameter ids " + std::to_string(ed->numParameters()) : "";
      std::printf("%-28s edge    dim %d  vertices %s%s  measurement %d%s  (%s)\n", e->tag.c_str(),
                  ed->dimension(), ed->arity() > 0 ? std::to_string(ed->arity()).c_str() : "any",
                  refers.c_str(), ed->measurementDataDimension(),
                  parameterNote(ed->parameterDataDimension()).c_str(), e->origin.c_str());
    }
  }
  return kExitOk;
}

int cmdListSolvers(const std::vector<std::string>& args) {
  Registries reg;
  if (!parseListing(args,
                    "usage: graphslam list-solvers [--plugin LIB]...\nLists the linear solvers "
                    "this build knows: name, system form (H: normal equations, J: whitened "
                    "Jacobian), orderings (the first is the default; pick one with "
                    "--solver NAME:ORDERING), description.",
                    reg)) {
    return kExitOk;
  }
  for (const auto* e : reg.solvers.entries()) {
    std::string orderings;
    for (Ordering o : e->orderings)
      orderings += (orderings.empty() ? "" : ",") + std::string(toString(o));
    std::printf("%-20s %-2s %-26s %s  (%s)\n", e->name.c_str(),
                e->form == SystemForm::kJacobian ? "J" : "H", orderings.c_str(),
                e->description.c_str(), e->origin.c_str());
  }
  std::printf("block-llt kernels: %s (GRAPHSLAM_SIMD=portable selects the portable ones)\n",
              solvers::blockKernelPath());
  return kExitOk;
}

}  // namespace graphslam::apps
