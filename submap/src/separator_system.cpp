// SPDX-License-Identifier: MIT
#include "separator_system.h"

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>

namespace graphslam::submap::detail {

SeparatorSystem::SeparatorSystem(const Partition& partition) : partition_(&partition) { clear(); }

void SeparatorSystem::clear() {
  triplets_.clear();
  const int n = partition_->separator_offsets.back();
  reduced_.setZero(n);
  gradient_.setZero(n);
}

void SeparatorSystem::add(int index, const Contribution& c) {
  const Submap& s = partition_->submaps[static_cast<std::size_t>(index)];
  // Local column -> separator system column.
  std::vector<int> global;
  global.reserve(static_cast<std::size_t>(s.separator_dimension));
  for (int k : s.separators) {
    const int first = partition_->separator_offsets[static_cast<std::size_t>(k)];
    const int last = partition_->separator_offsets[static_cast<std::size_t>(k) + 1];
    for (int col = first; col < last; ++col) global.push_back(col);
  }
  const auto n = static_cast<Eigen::Index>(global.size());
  for (Eigen::Index j = 0; j < n; ++j) {
    const int gj = global[static_cast<std::size_t>(j)];
    reduced_[gj] += c.reduced[j];
    gradient_[gj] += c.gradient[j];
    for (Eigen::Index i = 0; i <= j; ++i) {  // global columns increase with local ones
      const double value = c.schur(i, j);
      if (value != 0.0) triplets_.emplace_back(global[static_cast<std::size_t>(i)], gj, value);
    }
  }
}

bool SeparatorSystem::solve(double lambda, Eigen::VectorXd& step, std::string& message) const {
  const int n = partition_->separator_offsets.back();
  step.setZero(n);
  if (n == 0) return true;
  Eigen::SparseMatrix<double> s(n, n);
  s.setFromTriplets(triplets_.begin(), triplets_.end());
  if (lambda > 0) {
    for (int k = 0; k < n; ++k) s.coeffRef(k, k) += lambda;
  }
  nonzeros_ = static_cast<std::size_t>(s.nonZeros());
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Upper, Eigen::AMDOrdering<int>> llt(s);
  if (llt.info() != Eigen::Success) {
    message = "the separator system (" + std::to_string(partition_->separators.size()) +
              " vertices, dimension " + std::to_string(n) +
              ") is not positive definite: the separator vertices are not determined by the "
              "graph's edges (a free gauge, or too few measurements)";
    return false;
  }
  step = llt.solve(-reduced_);
  return true;
}

}  // namespace graphslam::submap::detail
