// SPDX-License-Identifier: MIT
#include "submap_system.h"

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>
#include <algorithm>

#ifdef GRAPHSLAM_SUBMAP_HAVE_CAMD
#include <camd.h>
#endif

#include "graphslam/core/edge.h"

namespace graphslam::submap::detail {

using SparseMatrix = Eigen::SparseMatrix<double>;
using Triplet = Eigen::Triplet<double>;

/// The submap's H and g: A (interior, upper triangle) and B (interior x separator) as
/// triplets, C dense, g in two parts.
struct SubmapSystem::Local {
  std::vector<Triplet> a, b;
  Eigen::MatrixXd c;
  Eigen::VectorXd g_interior, g_separator;
  double max_diagonal = 0.0;
};

/// The factorisation of A in the submap's elimination order (P A P^T = L L^T, natural order
/// inside the factorisation) with what back-substitution needs.
struct SubmapSystem::Factor {
  Eigen::SimplicialLLT<SparseMatrix, Eigen::Upper, Eigen::NaturalOrdering<int>> llt;
  SparseMatrix b;  ///< P B
  Eigen::VectorXd g_interior;
};

namespace {

#ifdef GRAPHSLAM_SUBMAP_HAVE_CAMD
/// The interior's part of CAMD's order of the pattern of [A B] with the separator's columns
/// constrained last: the interior ordered knowing which of its vertices the separator
/// joins (the fill AugmentedFactor's factorisation of M gets). Empty when CAMD fails.
std::vector<int> interiorOrderBeforeSeparator(const SparseMatrix& a_upper, const SparseMatrix& b) {
  const auto di = static_cast<int>(a_upper.rows()), n = di + static_cast<int>(b.cols());
  std::vector<int> starts(1, 0), rows, constraint(static_cast<std::size_t>(n), 0);
  rows.reserve(static_cast<std::size_t>(a_upper.nonZeros() + b.nonZeros()));
  for (int j = 0; j < di; ++j) {
    for (SparseMatrix::InnerIterator it(a_upper, j); it; ++it)
      rows.push_back(static_cast<int>(it.row()));
    starts.push_back(static_cast<int>(rows.size()));
  }
  for (int j = 0; j < b.cols(); ++j) {
    for (SparseMatrix::InnerIterator it(b, j); it; ++it) rows.push_back(static_cast<int>(it.row()));
    starts.push_back(static_cast<int>(rows.size()));
    constraint[static_cast<std::size_t>(di + j)] = 1;
  }
  std::vector<int> order(static_cast<std::size_t>(n));
  if (camd_order(n, starts.data(), rows.data(), order.data(), nullptr, nullptr,
                 b.cols() > 0 ? constraint.data() : nullptr) < CAMD_OK) {
    return {};
  }
  order.erase(std::remove_if(order.begin(), order.end(), [di](int k) { return k >= di; }),
              order.end());
  return order;
}
#endif

/// The elimination order of A: approximate minimum degree; when CAMD is available, either
/// knowing the separator last (`before_separator`: M's order for AugmentedFactor) or with
/// the rows B touches (the interior vertices next to the separator) constrained to the end,
/// so that L^-1 P B fills only the trailing rows. indices()[old] = new.
Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> eliminationOrder(
    const SparseMatrix& a_upper, const SparseMatrix& b, bool before_separator) {
  const auto n = static_cast<int>(a_upper.rows());
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> p(n);
#ifdef GRAPHSLAM_SUBMAP_HAVE_CAMD
  if (before_separator) {
    const std::vector<int> order = interiorOrderBeforeSeparator(a_upper, b);
    if (static_cast<int>(order.size()) == n) {
      for (int k = 0; k < n; ++k) p.indices()[order[static_cast<std::size_t>(k)]] = k;
      return p;
    }
  }
  std::vector<int> constraint(static_cast<std::size_t>(n), 0), order(static_cast<std::size_t>(n));
  for (int k = 0; k < b.outerSize(); ++k) {
    for (SparseMatrix::InnerIterator it(b, k); it; ++it)
      constraint[static_cast<std::size_t>(it.row())] = 1;
  }
  if (std::find(constraint.begin(), constraint.end(), 0) == constraint.end()) {
    std::fill(constraint.begin(), constraint.end(), 0);  // CAMD needs sets numbered below n
  }
  const int status = camd_order(n, a_upper.outerIndexPtr(), a_upper.innerIndexPtr(), order.data(),
                                nullptr, nullptr, constraint.data());
  if (status >= CAMD_OK) {
    for (int k = 0; k < n; ++k) p.indices()[order[static_cast<std::size_t>(k)]] = k;
    return p;
  }
#else
  (void)b;
  (void)before_separator;
#endif
  Eigen::AMDOrdering<int> amd;
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> inverse;
  const SparseMatrix full = a_upper.selfadjointView<Eigen::Upper>();
  amd(full, inverse);  // Eigen's orderings give the inverse: indices()[new] = old
  p = inverse.inverse();
  return p;
}

}  // namespace

SubmapSystem::SubmapSystem(const Partition& partition, int index, bool keep_factorization,
                           bool supernodal)
    : partition_(&partition),
      submap_(&partition.submaps[static_cast<std::size_t>(index)]),
      index_(index),
      keep_factorization_(keep_factorization),
      augmented_(supernodal ? std::make_unique<AugmentedFactor>() : nullptr) {
  int col = 0;
  columns_.reserve(submap_->interior.size() + submap_->separators.size());
  for (const Vertex* v : submap_->interior) {
    columns_.emplace(v, col);
    col += v->dimension();
  }
  col = 0;
  for (int s : submap_->separators) {
    const Vertex* v = partition.separators[static_cast<std::size_t>(s)];
    columns_.emplace(v, -2 - col);
    col += v->dimension();
  }
}

SubmapSystem::~SubmapSystem() = default;
SubmapSystem::SubmapSystem(SubmapSystem&&) noexcept = default;

double SubmapSystem::cost() {
  double sum = 0.0;
  for (Edge* e : submap_->edges) {
    e->computeError();
    sum += e->robustChi2();
  }
  return sum;
}

double SubmapSystem::rawChi2() const {
  double sum = 0.0;
  for (const Edge* e : submap_->edges) sum += e->chi2();
  return sum;
}

bool SubmapSystem::linearize() {
  bool in_place = false;
  for (Edge* e : submap_->edges) {
    e->linearizeOplus();
    if (e->perturbsVerticesInPlace()) {
      e->computeError();  // the numeric Jacobian left the error of a perturbed estimate
      in_place = true;
    }
  }
  return in_place;
}

namespace {

/// Adds block (a, b) = M (rows of slot a, columns of slot b) of an edge's quadratic form to
/// the local system, given the slots' columns (interior >= 0, separator -2 - col).
void scatterBlock(const Eigen::Ref<const Eigen::MatrixXd>& m, int col_a, int col_b, bool diagonal,
                  std::vector<Triplet>& a, std::vector<Triplet>& b, Eigen::MatrixXd& c) {
  const auto rows = static_cast<int>(m.rows()), cols = static_cast<int>(m.cols());
  if (col_a >= 0 && col_b >= 0) {  // interior x interior: the upper triangle of A
    for (int j = 0; j < cols; ++j) {
      for (int i = 0; i < rows; ++i) {
        if (diagonal && i > j) continue;
        if (col_a <= col_b) {
          a.emplace_back(col_a + i, col_b + j, m(i, j));
        } else {
          a.emplace_back(col_b + j, col_a + i, m(i, j));
        }
      }
    }
  } else if (col_a >= 0 || col_b >= 0) {  // interior x separator: B
    const bool a_interior = col_a >= 0;
    const int ci = a_interior ? col_a : col_b, cs = -2 - (a_interior ? col_b : col_a);
    for (int j = 0; j < cols; ++j) {
      for (int i = 0; i < rows; ++i) {
        if (a_interior) {
          b.emplace_back(ci + i, cs + j, m(i, j));
        } else {
          b.emplace_back(ci + j, cs + i, m(i, j));
        }
      }
    }
  } else {  // separator x separator: C, both triangles
    const int sa = -2 - col_a, sb = -2 - col_b;
    c.block(sa, sb, rows, cols) += m;
    if (!diagonal) c.block(sb, sa, cols, rows) += m.transpose();
  }
}

}  // namespace

void SubmapSystem::assemble(Local& local, double lambda) const {
  const int di = submap_->interior_dimension, ds = submap_->separator_dimension;
  local.c.setZero(ds, ds);
  local.g_interior.setZero(di);
  local.g_separator.setZero(ds);
  local.a.clear();
  local.b.clear();
  Eigen::MatrixXd h;
  Eigen::VectorXd g;
  std::vector<HessianBlockRef> blocks;
  std::vector<int> offsets, b_offsets, cols, dims;
  for (const Edge* e : submap_->edges) {
    const int n = static_cast<int>(e->numVertices());
    offsets.assign(static_cast<std::size_t>(n) + 1, 0);
    cols.assign(static_cast<std::size_t>(n), -1);
    dims.assign(static_cast<std::size_t>(n), 0);
    for (int k = 0; k < n; ++k) {
      const Vertex* v = e->vertex(static_cast<std::size_t>(k));
      const auto it = columns_.find(v);
      dims[k] = v->dimension();
      cols[k] = it == columns_.end() ? -1 : it->second;  // -1: fixed
      offsets[k + 1] = offsets[k] + dims[k];
    }
    const int d = offsets[n];
    h.setZero(d, d);
    g.setZero(d);
    blocks.assign(static_cast<std::size_t>(n * (n + 1) / 2), HessianBlockRef{});
    b_offsets.assign(static_cast<std::size_t>(n), -1);
    for (int x = 0; x < n; ++x) {
      if (cols[x] == -1) continue;
      b_offsets[x] = offsets[x];
      for (int y = x; y < n; ++y) {
        if (cols[y] == -1) continue;
        blocks[upperPairIndex(x, y, n)] = HessianBlockRef{offsets[x] + offsets[y] * d, d, false};
      }
    }
    e->constructQuadraticForm(
        QuadraticFormTarget{h.data(), g.data(), blocks.data(), b_offsets.data()});
    for (int x = 0; x < n; ++x) {
      if (cols[x] == -1) continue;
      const auto seg = g.segment(offsets[x], dims[x]);
      if (cols[x] >= 0) {
        local.g_interior.segment(cols[x], dims[x]) += seg;
      } else {
        local.g_separator.segment(-2 - cols[x], dims[x]) += seg;
      }
      for (int y = x; y < n; ++y) {
        if (cols[y] == -1) continue;
        scatterBlock(h.block(offsets[x], offsets[y], dims[x], dims[y]), cols[x], cols[y], x == y,
                     local.a, local.b, local.c);
      }
    }
  }
  for (const Triplet& t : local.a) {
    if (t.row() == t.col()) local.max_diagonal = std::max(local.max_diagonal, t.value());
  }
  if (ds > 0) local.max_diagonal = std::max(local.max_diagonal, local.c.diagonal().maxCoeff());
  if (lambda > 0) {
    for (int k = 0; k < di; ++k) local.a.emplace_back(k, k, lambda);
  }
}

std::unique_ptr<SubmapSystem::Factor> SubmapSystem::factorize(const Local& local,
                                                              std::string& message) {
  const int di = submap_->interior_dimension, ds = submap_->separator_dimension;
  auto f = std::make_unique<Factor>();
  SparseMatrix a(di, di), b(di, ds);
  a.setFromTriplets(local.a.begin(), local.a.end());
  b.setFromTriplets(local.b.begin(), local.b.end());
  f->g_interior = local.g_interior;
  if (di == 0) return f;
  if (order_.size() != di) {  // the structure never changes
    order_ = eliminationOrder(a, b, augmented_ != nullptr);
  }
  f->b = order_ * b;
  f->g_interior = order_ * local.g_interior;
  SparseMatrix permuted(di, di);
  permuted.selfadjointView<Eigen::Upper>() = a.selfadjointView<Eigen::Upper>().twistedBy(order_);
  bool factorized = false;
  if (augmented_) {
    // The shift of the separator block: C's largest diagonal entry (AugmentedFactor).
    const double c_max = ds > 0 ? local.c.diagonal().maxCoeff() : 0.0;
    const double delta = c_max > 0 ? c_max : std::max(local.max_diagonal, 1.0);
    factorized = augmented_->factorize(permuted, f->b, local.c, delta);
  } else {
    f->llt.compute(permuted);
    factorized = f->llt.info() == Eigen::Success;
  }
  if (!factorized) {
    const auto& v = submap_->interior;
    message = "submap " + std::to_string(index_) + " (" + std::to_string(v.size()) +
              " interior vertices, ids " + std::to_string(v.front()->id()) + " to " +
              std::to_string(v.back()->id()) +
              "): its interior system is not positive definite (vertices its edges and "
              "separator do not determine, or a numerical breakdown)";
    return nullptr;
  }
  return f;
}

namespace {

/// Y's trailing rows are taken dense while they hold at most this many times the doubles of
/// the dense separator block itself (it is in memory anyway); beyond, the sparse product.
constexpr Eigen::Index kDenseRowsPerSeparatorBlock = 16;

/// schur -= Y^T Y and reduced -= Y^T z for Y = L^-1 P B, z = L^-1 P g_I. Y is zero above its
/// first non-zero row (L is lower triangular and P puts the rows B touches last), so the
/// rows below are taken dense (kDenseRowsPerSeparatorBlock), the product by BLAS-3.
void subtractProjection(const SparseMatrix& y, const Eigen::VectorXd& z, Eigen::MatrixXd& schur,
                        Eigen::VectorXd& reduced) {
  const auto rows = y.rows(), cols = y.cols();
  Eigen::Index first = rows;
  for (Eigen::Index k = 0; k < y.outerSize(); ++k) {
    for (SparseMatrix::InnerIterator it(y, k); it; ++it) first = std::min(first, it.row());
  }
  const Eigen::Index height = rows - first;
  if (height <= kDenseRowsPerSeparatorBlock * std::max<Eigen::Index>(cols, 64)) {
    Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(height, cols);
    for (Eigen::Index k = 0; k < y.outerSize(); ++k) {
      for (SparseMatrix::InnerIterator it(y, k); it; ++it) dense(it.row() - first, k) = it.value();
    }
    schur.selfadjointView<Eigen::Lower>().rankUpdate(dense.transpose(), -1.0);
    schur.triangularView<Eigen::StrictlyUpper>() = schur.transpose();
    reduced.noalias() -= dense.transpose() * z.tail(height);
    return;
  }
  schur -= Eigen::MatrixXd(SparseMatrix(y.transpose() * y));
  reduced.noalias() -= y.transpose() * z;
}

}  // namespace

Contribution SubmapSystem::eliminate(double lambda) {
  Contribution out;
  kept_.reset();
  Local local;
  assemble(local, lambda);
  out.max_diagonal = local.max_diagonal;
  out.interior_gradient_squared = local.g_interior.squaredNorm();
  out.gradient = local.g_separator;
  auto f = factorize(local, out.message);
  if (!f) {
    out.ok = false;
    return out;
  }
  out.schur = std::move(local.c);
  out.reduced = local.g_separator;
  if (augmented_ && submap_->interior_dimension > 0 && submap_->separator_dimension > 0) {
    augmented_->contribution(f->g_interior, local.g_separator, out.schur, out.reduced);
  } else if (submap_->interior_dimension > 0 && submap_->separator_dimension > 0) {
    SparseMatrix y = f->b;
    f->llt.matrixL().solveInPlace(y);
    Eigen::VectorXd z = f->g_interior;
    f->llt.matrixL().solveInPlace(z);
    subtractProjection(y, z, out.schur, out.reduced);
  }
  if (keep_factorization_) {
    kept_ = std::move(f);
  } else if (augmented_) {
    augmented_->release();
  }
  return out;
}

Contribution SubmapSystem::gradient() const {
  Contribution out;
  Local local;
  assemble(local, 0.0);
  out.interior_gradient_squared = local.g_interior.squaredNorm();
  out.gradient = std::move(local.g_separator);
  return out;
}

bool SubmapSystem::backSubstitute(const Eigen::VectorXd& separator_step, double lambda,
                                  Eigen::VectorXd& interior_step, std::string& message) {
  std::unique_ptr<Factor> f = std::move(kept_);
  if (!f) {
    Local local;
    assemble(local, lambda);
    f = factorize(local, message);
    if (!f) return false;
  }
  if (submap_->interior_dimension == 0) {
    interior_step.resize(0);
    return true;
  }
  Eigen::VectorXd rhs = -f->g_interior;
  if (separator_step.size() > 0) rhs.noalias() -= f->b * separator_step;
  if (augmented_) {
    interior_step = order_.transpose() * augmented_->solveInterior(rhs);
    augmented_->release();
  } else {
    interior_step = order_.transpose() * f->llt.solve(rhs);
  }
  return true;
}

void SubmapSystem::applyInterior(const Eigen::VectorXd& interior_step) {
  saved_ = interiorEstimates();
  int col = 0;
  for (Vertex* v : submap_->interior) {
    v->oplus(interior_step.data() + col);
    col += v->dimension();
  }
}

void SubmapSystem::restoreInterior() {
  if (!saved_.empty()) setInteriorEstimates(saved_);
}

std::vector<double> SubmapSystem::interiorEstimates() const {
  std::vector<double> data;
  for (const Vertex* v : submap_->interior) {
    const std::size_t at = data.size();
    data.resize(at + static_cast<std::size_t>(v->estimateDataDimension()));
    v->getEstimateData(data.data() + at);
  }
  return data;
}

void SubmapSystem::setInteriorEstimates(const std::vector<double>& data) {
  std::size_t at = 0;
  for (Vertex* v : submap_->interior) {
    v->setEstimateData(data.data() + at);
    at += static_cast<std::size_t>(v->estimateDataDimension());
  }
}

}  // namespace graphslam::submap::detail
