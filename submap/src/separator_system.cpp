// SPDX-License-Identifier: MIT
#include "separator_system.h"

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <map>

#include "separator_cg.h"

namespace graphslam::submap::detail {

/// The separator system in the layout of SparseStructure (upper triangle, full diagonal
/// blocks, complete blocks): one block per separator vertex, a block (a, b) wherever a
/// submap touches both.
struct SeparatorSystem::Blocked {
  std::unique_ptr<LinearSolver> solver;
  std::vector<int> col_ptr, row_idx, block_starts;
  /// Per column block: (row block, first row of it within the block's columns), by row block.
  std::vector<std::vector<std::pair<int, int>>> rows;
  std::vector<double> values;
  std::vector<int> diagonal;  // positions of the diagonal entries
  bool analysed = false;

  [[nodiscard]] double* at(int a, int b) {  // (0, 0) of block (a, b), a <= b
    const auto& list = rows[static_cast<std::size_t>(b)];
    const auto it = std::lower_bound(list.begin(), list.end(), std::make_pair(a, -1));
    return values.data() +
           col_ptr[static_cast<std::size_t>(block_starts[static_cast<std::size_t>(b)])] +
           it->second;
  }
};

namespace {

void buildStructure(const Partition& p, SeparatorSystem::Blocked& s) {
  const std::size_t nb = p.separators.size();
  std::vector<std::vector<int>> row_blocks(nb);
  for (const Submap& sm : p.submaps) {
    for (std::size_t j = 0; j < sm.separators.size(); ++j) {
      auto& list = row_blocks[static_cast<std::size_t>(sm.separators[j])];
      list.insert(list.end(), sm.separators.begin(),
                  sm.separators.begin() + static_cast<std::ptrdiff_t>(j) + 1);
    }
  }
  s.block_starts = p.separator_offsets;
  s.rows.resize(nb);
  s.col_ptr.assign(1, 0);
  for (std::size_t b = 0; b < nb; ++b) {
    auto& list = row_blocks[b];
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    int height = 0;
    for (int a : list) {
      s.rows[b].emplace_back(a, height);
      height += p.separator_offsets[static_cast<std::size_t>(a) + 1] -
                p.separator_offsets[static_cast<std::size_t>(a)];
    }
    const int first = p.separator_offsets[b], last = p.separator_offsets[b + 1];
    for (int col = first; col < last; ++col) {
      for (int a : list) {
        for (int r = p.separator_offsets[static_cast<std::size_t>(a)];
             r < p.separator_offsets[static_cast<std::size_t>(a) + 1]; ++r) {
          s.row_idx.push_back(r);
        }
      }
      s.diagonal.push_back(s.col_ptr.back() + s.rows[b].back().second + (col - first));
      s.col_ptr.push_back(static_cast<int>(s.row_idx.size()));
    }
    std::vector<int>().swap(list);
  }
  s.values.assign(s.row_idx.size(), 0.0);
}

/// Adds a submap's Schur complement block by block (its separator list increases, so its
/// block (i, j), i <= j, is the system's upper block (a, b)).
void addBlocks(const Partition& p, const Submap& sm, const Contribution& c,
               SeparatorSystem::Blocked& s) {
  int cj = 0;
  for (std::size_t j = 0; j < sm.separators.size(); ++j) {
    const int b = sm.separators[j];
    const int db = p.separator_offsets[static_cast<std::size_t>(b) + 1] -
                   p.separator_offsets[static_cast<std::size_t>(b)];
    const int height =
        s.col_ptr[static_cast<std::size_t>(p.separator_offsets[static_cast<std::size_t>(b)]) + 1] -
        s.col_ptr[static_cast<std::size_t>(p.separator_offsets[static_cast<std::size_t>(b)])];
    int ci = 0;
    for (std::size_t i = 0; i <= j; ++i) {
      const int a = sm.separators[i];
      const int da = p.separator_offsets[static_cast<std::size_t>(a) + 1] -
                     p.separator_offsets[static_cast<std::size_t>(a)];
      double* block = s.at(a, b);
      for (int y = 0; y < db; ++y) {
        for (int x = 0; x < da; ++x) block[y * height + x] += c.schur(ci + x, cj + y);
      }
      ci += da;
    }
    cj += db;
  }
}

/// Numbers the separator vertices' aggregates: vertices touched by the same submaps share
/// one, numbered in order of their first vertex. Returns the count.
int aggregateBySubmaps(const Partition& p, std::vector<int>& aggregate) {
  std::vector<std::vector<int>> touching(p.separators.size());
  for (std::size_t k = 0; k < p.submaps.size(); ++k) {
    for (int v : p.submaps[k].separators) {
      touching[static_cast<std::size_t>(v)].push_back(static_cast<int>(k));
    }
  }
  std::map<std::vector<int>, int> number;
  aggregate.resize(p.separators.size());
  for (std::size_t v = 0; v < touching.size(); ++v) {
    aggregate[v] =
        number.emplace(std::move(touching[v]), static_cast<int>(number.size())).first->second;
  }
  return static_cast<int>(number.size());
}

}  // namespace

SeparatorSystem::SeparatorSystem(const Partition& partition, const Options& options, bool solves)
    : partition_(&partition),
      cg_(options.separator_method == Options::SeparatorMethod::conjugate_gradients),
      cg_tolerance_(options.separator_cg_tolerance),
      cg_max_iterations_(options.separator_cg_max_iterations),
      cg_local_dimension_(options.separator_cg_local_dimension),
      cg_coarse_(options.separator_cg_coarse) {
  if (solves && (cg_ || options.solvers != nullptr) && !partition.separators.empty()) {
    auto blocked = std::make_unique<Blocked>();
    if (!cg_) blocked->solver = options.solvers->create(options.separator_solver);
    buildStructure(partition, *blocked);
    blocked_ = std::move(blocked);
    if (cg_ && (cg_coarse_ || cg_local_dimension_ > 0)) {
      num_aggregates_ = aggregateBySubmaps(partition, aggregates_);
    }
  }
  clear();
}

SeparatorSystem::~SeparatorSystem() = default;

void SeparatorSystem::clear() {
  triplets_.clear();
  if (blocked_) std::fill(blocked_->values.begin(), blocked_->values.end(), 0.0);
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
  if (blocked_) {
    addBlocks(*partition_, s, c, *blocked_);
    for (Eigen::Index j = 0; j < n; ++j) {
      reduced_[global[static_cast<std::size_t>(j)]] += c.reduced[j];
      gradient_[global[static_cast<std::size_t>(j)]] += c.gradient[j];
    }
    return;
  }
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

bool SeparatorSystem::solveBlocked(double lambda, Eigen::VectorXd& step,
                                   std::string& message) const {
  Blocked& s = *blocked_;
  const int n = partition_->separator_offsets.back();
  const SparseStructure structure{n, s.col_ptr.data(), s.row_idx.data(), s.block_starts.data(),
                                  static_cast<int>(partition_->separators.size())};
  if (!s.analysed) {
    if (!s.solver->preferredBlockOrder(structure).empty()) {
      message = "the separator solver " + s.solver->name() +
                " asks for its own block order, which the separator system does not provide";
      return false;
    }
    const LinearSolverResult r = s.solver->analyze(structure);
    if (!r.ok()) {
      message = "the separator system: " + r.message;
      return false;
    }
    s.analysed = true;
  }
  std::vector<double> values = s.values;
  for (int d : s.diagonal) values[static_cast<std::size_t>(d)] += lambda;
  nonzeros_ = values.size();
  LinearSolverResult r = s.solver->factorize(values.data());
  if (r.ok()) {
    const Eigen::VectorXd rhs = -reduced_;
    r = s.solver->solve(rhs.data(), step.data());
  }
  if (!r.ok()) {
    message = "the separator system (" + std::to_string(partition_->separators.size()) +
              " vertices, dimension " + std::to_string(n) + ") does not factorise: " + r.message;
    return false;
  }
  return true;
}

bool SeparatorSystem::solveByCg(double lambda, Eigen::VectorXd& step, std::string& message) const {
  const Blocked& s = *blocked_;
  const int n = partition_->separator_offsets.back();
  const BlockUpperCsc matrix{n,
                             s.col_ptr.data(),
                             s.row_idx.data(),
                             s.values.data(),
                             s.diagonal.data(),
                             s.block_starts.data(),
                             static_cast<int>(partition_->separators.size()),
                             aggregates_.empty() ? nullptr : aggregates_.data(),
                             num_aggregates_};
  nonzeros_ = s.values.size();
  const CgOutcome out =
      solveByConjugateGradients(matrix, lambda, -reduced_, step, cg_tolerance_, cg_max_iterations_,
                                {cg_coarse_, cg_local_dimension_});
  iterations_ = out.iterations;
  if (!out.ok) {
    message = "the separator system (" + std::to_string(partition_->separators.size()) +
              " vertices, dimension " + std::to_string(n) + ") not solved: " + out.message;
  }
  return out.ok;
}

bool SeparatorSystem::solve(double lambda, Eigen::VectorXd& step, std::string& message) const {
  const int n = partition_->separator_offsets.back();
  step.setZero(n);
  iterations_ = 0;
  if (n == 0) return true;
  if (blocked_ && cg_) return solveByCg(lambda, step, message);
  if (blocked_) return solveBlocked(lambda, step, message);
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
