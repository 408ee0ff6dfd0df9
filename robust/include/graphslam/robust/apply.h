// SPDX-License-Identifier: MIT
#pragma once

#include <cmath>
#include <cstddef>
#include <limits>
#include <memory>
#include <string>

#include "graphslam/core/edge.h"
#include "graphslam/core/graph.h"
#include "graphslam/core/robust_kernel.h"
#include "graphslam/core/type_registry.h"

namespace graphslam::robust {

/// A kernel named on the command line: "NAME" or "NAME:WIDTH".
struct KernelSpec {
  std::string name;
  /// NaN: the kernel's registered default width.
  double width = std::numeric_limits<double>::quiet_NaN();
};

/// Parses "NAME[:WIDTH]" against the kernels of `registry`. Throws RegistryError, naming the
/// registered kernels, for an empty or unknown name, an empty width ("huber:"), a width that
/// is not a number ("huber:abc") or not positive and finite ("huber:-1", "huber:inf").
[[nodiscard]] KernelSpec parseKernelSpec(const std::string& spec, const KernelRegistry& registry);

/// The kernel `spec` names, made by the registry (its default width when none is given).
[[nodiscard]] std::shared_ptr<RobustKernel> createKernel(const KernelSpec& spec,
                                                         const KernelRegistry& registry);

/// Which edges get a kernel.
enum class EdgeSelection {
  kAll,           ///< every edge (g2o's -robustKernel)
  kLoopClosures,  ///< see isLoopClosure
  kTag,           ///< edges whose registered .g2o tag is EdgeSelector::tag
};

struct EdgeSelector {
  EdgeSelection kind = EdgeSelection::kAll;
  std::string tag;  ///< for kTag
};

/// Parses "all", "loop-closures" or an edge tag registered in `registry`. Throws
/// RegistryError for anything else, naming the registered edge tags.
[[nodiscard]] EdgeSelector parseEdgeSelection(const std::string& text,
                                              const TypeRegistry& registry);

/// A loop closure: an edge between exactly two vertices that are poses of one trajectory
/// — vertices of the same dynamic type and tangent dimension (two VERTEX_SE2; a pose-landmark
/// edge joins two different types) — whose ids are not consecutive (|i - j| != 1; odometry
/// joins consecutive ids in the .g2o convention).
[[nodiscard]] bool isLoopClosure(const Edge& edge, const Graph& graph);

/// Whether `selector` selects `edge` (its tag looked up in `registry`).
[[nodiscard]] bool selects(const EdgeSelector& selector, const Edge& edge, const Graph& graph,
                           const TypeRegistry& registry);

/// Gives `kernel` (shared by all of them; nullptr removes kernels) to the edges `selector`
/// selects; returns their number. Other edges keep what they had.
std::size_t applyRobustKernel(Graph& graph, const std::shared_ptr<const RobustKernel>& kernel,
                              const EdgeSelector& selector, const TypeRegistry& registry);

/// The same from text: `kernel_spec` is "NAME[:WIDTH]", `selection` "all", "loop-closures" or
/// an edge tag. Throws RegistryError (a graphslam::Error) for malformed specs or selections.
std::size_t applyRobustKernel(Graph& graph, const TypeRegistry& types,
                              const KernelRegistry& kernels, const std::string& kernel_spec,
                              const std::string& selection = "all");

}  // namespace graphslam::robust
