// SPDX-License-Identifier: MIT
#include "robust_options.h"

#include <cstdio>
#include <iostream>

#include "cli_common.h"
#include "graphslam/robust/apply.h"
#include "graphslam/support/error.h"

namespace graphslam::apps {

namespace {

std::string selectionText(const RobustOptions& o) { return o.edges.empty() ? "all" : o.edges; }

}  // namespace

void declareRobustOptions(po::options_description& desc, RobustOptions& o) {
  desc.add_options()(
      "robust-kernel", po::value(&o.kernel)->value_name("NAME[:WIDTH]"),
      "robust kernel on the edges --robust-edges selects (graphslam list-kernels shows the "
      "kernels and their default widths); the summary then shows chi2 and the robust cost")(
      "robust-edges", po::value(&o.edges)->value_name("all|loop-closures|TAG"),
      "edges that get the kernel: all (the default, as g2o's -robustKernel), loop-closures "
      "(edges between two vertices of the same type whose ids are not consecutive) or the "
      "edges of one .g2o tag");
}

void checkRobustOptions(const RobustOptions& o, const Registries& reg) {
  if (o.kernel.empty()) {
    if (!o.edges.empty()) throw UsageError("--robust-edges needs --robust-kernel NAME[:WIDTH]");
    return;
  }
  try {
    (void)robust::parseKernelSpec(o.kernel, reg.kernels);
  } catch (const RegistryError& e) {
    throw UsageError(std::string("--robust-kernel: ") + e.what());
  }
  try {
    (void)robust::parseEdgeSelection(selectionText(o), reg.types);
  } catch (const RegistryError& e) {
    throw UsageError(std::string("--robust-edges: ") + e.what());
  }
}

void applyRobustOptions(const RobustOptions& o, Graph& graph, const Registries& reg) {
  if (o.kernel.empty()) return;
  const robust::KernelSpec spec = robust::parseKernelSpec(o.kernel, reg.kernels);
  const auto kernel = robust::createKernel(spec, reg.kernels);
  const robust::EdgeSelector selector = robust::parseEdgeSelection(selectionText(o), reg.types);
  const std::size_t n = robust::applyRobustKernel(graph, kernel, selector, reg.types);
  std::printf("robust kernel %s (width %.6g) on %zu of %zu edges (%s)\n", spec.name.c_str(),
              kernel->width(), n, graph.numEdges(), selectionText(o).c_str());
  if (n == 0) {
    std::cerr << "warning: --robust-edges " << selectionText(o)
              << " selects no edge of this graph: the kernel has no effect\n";
  }
}

int cmdListKernels(const std::vector<std::string>& args) {
  Registries reg;
  if (!parseListing(args,
                    "usage: graphslam list-kernels [--plugin LIB]...\nLists the robust kernels "
                    "this build knows (for optimize --robust-kernel NAME[:WIDTH]): name, default "
                    "width, origin.",
                    reg)) {
    return kExitOk;
  }
  for (const auto* k : reg.kernels.entries()) {
    std::printf("%-16s width %-10.6g (%s)\n", k->name.c_str(), k->default_width, k->origin.c_str());
  }
  return kExitOk;
}

}  // namespace graphslam::apps
