// SPDX-License-Identifier: MIT
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace graphslam {

/// A robust kernel rho replaces an edge's squared error s = e^T Omega e in the objective
/// by rho(s), which grows more slowly than s for large errors, so that a few wrong
/// measurements cannot pull the whole estimate. As in g2o, the optimizer uses the
/// first-order weighting: the edge enters H and b with its information scaled by rho'(s)
/// (iteratively reweighted least squares), and its cost is rho(s).
///
/// Kernels are registered by name in a KernelRegistry (KernelRegistry::registerKernel), so
/// plugins can add their own; an edge holds one through Edge::setRobustKernel (several
/// edges may share one kernel object: kernels are immutable once made, apart from what a
/// derived class documents).
class RobustKernel {
 public:
  /// `width` is the kernel's scale (g2o's delta): where rho starts to deviate from s,
  /// in units of the error's Mahalanobis length (s = width^2 is the bend).
  explicit RobustKernel(double width = 1.0) : width_(width) {}
  virtual ~RobustKernel() = default;
  RobustKernel(const RobustKernel&) = delete;
  RobustKernel& operator=(const RobustKernel&) = delete;

  /// rho(s), rho'(s) and rho''(s) for the squared error s >= 0 (g2o's convention: rho(s) ~ s
  /// for small s, so rho'(0) = 1).
  virtual void robustify(double squared_error, double rho[3]) const = 0;

  [[nodiscard]] double width() const { return width_; }

 private:
  double width_;
};

/// Makes a kernel of the given width (> 0, finite; checked by the registry).
using RobustKernelFactory = std::function<std::shared_ptr<RobustKernel>(double width)>;

/// Maps names to robust kernels ("huber", "cauchy", ...), each with the width used when none
/// is given. Filled by explicit registration (`robust::registerKernels(registry)`) and by
/// plugins; each program or test owns its registry.
class KernelRegistry {
 public:
  struct Entry {
    std::string name;
    double default_width = 1.0;
    std::string origin;  ///< module or plugin that registered it
    RobustKernelFactory make;
  };
  /// Registers a kernel. Throws RegistryError on a duplicate or malformed name, a null
  /// factory or a default width that is not positive and finite.
  void registerKernel(const std::string& name, double default_width, RobustKernelFactory factory);
  /// Label stored with the next registrations (e.g. "robust", a plugin's path).
  void setOrigin(std::string origin) { origin_ = std::move(origin); }

  [[nodiscard]] const Entry* find(const std::string& name) const;
  [[nodiscard]] bool contains(const std::string& name) const { return find(name) != nullptr; }
  /// Kernel `name` of width `width` (NaN: its default width). Throws RegistryError for an
  /// unknown name (listing the known ones) or a width that is not positive and finite.
  [[nodiscard]] std::shared_ptr<RobustKernel> create(const std::string& name, double width) const;
  /// All kernels sorted by name.
  [[nodiscard]] std::vector<const Entry*> entries() const;

 private:
  std::map<std::string, Entry> entries_;
  std::string origin_;
};

}  // namespace graphslam
