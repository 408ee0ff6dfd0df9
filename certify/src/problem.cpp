// SPDX-License-Identifier: MIT
#include "graphslam/certify/problem.h"

#include <cmath>
#include <numeric>
#include <string>

#include "graphslam/support/error.h"
#include "problem_impl.h"

namespace graphslam::certify {

namespace {

using Triplets = std::vector<Eigen::Triplet<double>>;

/// Checks a measurement's shape and weights; throws InputError naming it.
void checkMeasurement(const Measurement& m, std::size_t k, int d, int n) {
  const std::string which = "measurement " + std::to_string(k) + " (poses " + std::to_string(m.i) +
                            ", " + std::to_string(m.j) + ")";
  if (m.i < 0 || m.j < 0 || m.i >= n || m.j >= n || m.i == m.j) {
    throw InputError(which + ": pose indices must be distinct and in [0, " + std::to_string(n) +
                     ")");
  }
  if (m.rotation.rows() != d || m.rotation.cols() != d || m.translation.size() != d) {
    throw InputError(which + ": rotation or translation of the wrong size");
  }
  if (!(std::isfinite(m.kappa) && m.kappa > 0.0)) {
    throw InputError(which + ": no positive rotation weight (missing rotation information)");
  }
  if (!(std::isfinite(m.tau) && m.tau > 0.0)) {
    throw InputError(which + ": no positive translation weight");
  }
  if (!m.rotation.allFinite() || !m.translation.allFinite()) {
    throw InputError(which + ": a value is not finite");
  }
}

/// The triplets of M (full, translations of all n poses first, then the dn rotation rows).
Triplets assemble(const std::vector<Measurement>& ms, int d, int n) {
  Triplets t;
  t.reserve(ms.size() * static_cast<std::size_t>(4 * d * d + 6 * d + 8));
  auto rot = [n, d](int pose, int row) { return n + d * pose + row; };
  for (const Measurement& m : ms) {
    for (int a = 0; a < d; ++a) {
      t.emplace_back(rot(m.i, a), rot(m.i, a), m.kappa);
      t.emplace_back(rot(m.j, a), rot(m.j, a), m.kappa);
      for (int b = 0; b < d; ++b) {
        t.emplace_back(rot(m.i, a), rot(m.j, b), -m.kappa * m.rotation(a, b));
        t.emplace_back(rot(m.j, b), rot(m.i, a), -m.kappa * m.rotation(a, b));
        t.emplace_back(rot(m.i, a), rot(m.i, b), m.tau * m.translation(a) * m.translation(b));
      }
      // a = (+1 at t_j, -1 at t_i, -t~ at X_i's rows); M += tau a a^T
      const double w = m.tau * m.translation(a);
      t.emplace_back(m.j, rot(m.i, a), -w);
      t.emplace_back(rot(m.i, a), m.j, -w);
      t.emplace_back(m.i, rot(m.i, a), w);
      t.emplace_back(rot(m.i, a), m.i, w);
    }
    t.emplace_back(m.i, m.i, m.tau);
    t.emplace_back(m.j, m.j, m.tau);
    t.emplace_back(m.i, m.j, -m.tau);
    t.emplace_back(m.j, m.i, -m.tau);
  }
  // Every entry of the rotation rows' diagonal blocks is stored (Lambda is subtracted there).
  for (int i = 0; i < n; ++i) {
    for (int a = 0; a < d; ++a) {
      for (int b = 0; b < d; ++b) t.emplace_back(rot(i, a), rot(i, b), 0.0);
    }
  }
  return t;
}

}  // namespace

int unconnectedPose(const std::vector<Measurement>& ms, int n, int* components) {
  std::vector<int> parent(static_cast<std::size_t>(n));
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  *components = n;
  for (const Measurement& m : ms) {
    const int a = find(m.i), b = find(m.j);
    if (a != b) parent[std::max(a, b)] = std::min(a, b), --*components;
  }
  for (int i = 1; i < n; ++i) {
    if (find(i) != 0) return i;
  }
  return -1;
}

Problem::Problem(int d, int num_poses, std::vector<Measurement> measurements)
    : d_(d),
      n_(num_poses),
      measurements_(std::move(measurements)),
      impl_(std::make_unique<Impl>()) {
  if (d != 2 && d != 3) throw InputError("certify: the pose dimension must be 2 or 3");
  if (n_ < 2) throw InputError("certify: the graph needs at least two poses");
  for (std::size_t k = 0; k < measurements_.size(); ++k)
    checkMeasurement(measurements_[k], k, d, n_);
  int components = 1;
  if (const int other = unconnectedPose(measurements_, n_, &components); other >= 0) {
    throw InputError("the poses are not connected: " + std::to_string(components) +
                     " components (pose " + std::to_string(other) +
                     " is not connected to pose 0); SE-Sync's relaxation needs one connected "
                     "pose graph");
  }
  const Triplets triplets = assemble(measurements_, d_, n_);
  const int size = n_ + d_ * n_;
  SparseMatrix m(size, size);
  m.setFromTriplets(triplets.begin(), triplets.end());
  Impl& p = *impl_;
  const int dn = d_ * n_;
  // M' drops the first translation: rows/columns 1.. of M.
  p.k = m.bottomRightCorner(size - 1, size - 1).triangularView<Eigen::Lower>();
  p.mxx = m.bottomRightCorner(dn, dn);
  p.mxt = m.block(n_, 1, dn, n_ - 1);
  p.mtx = p.mxt.transpose();
  const SparseMatrix ltt = m.block(1, 1, n_ - 1, n_ - 1);
  p.ltt.compute(ltt);
  if (p.ltt.info() != Eigen::Success) {
    throw InputError("certify: the translation Laplacian is not positive definite");
  }
  p.block_entries.assign(static_cast<std::size_t>(n_ * d_ * d_), -1);
  const int offset = n_ - 1;
  for (int i = 0; i < n_; ++i) {
    for (int b = 0; b < d_; ++b) {
      const int col = offset + d_ * i + b;
      for (SparseMatrix::InnerIterator it(p.k, col); it; ++it) {
        const int a = static_cast<int>(it.row()) - offset - d_ * i;
        if (a >= b && a < d_) {
          p.block_entries[static_cast<std::size_t>(i * d_ * d_ + a * d_ + b)] =
              static_cast<int>(&it.valueRef() - p.k.valuePtr());
        }
      }
    }
  }
  for (int r = 0; r < dn; ++r) {
    double s = 0.0;
    for (SparseMatrix::InnerIterator it(p.mxx, r); it; ++it) s += std::abs(it.value());
    scale_ = std::max(scale_, s);
  }
}

Problem::Problem(Problem&&) noexcept = default;
Problem& Problem::operator=(Problem&&) noexcept = default;
Problem::~Problem() = default;

Eigen::MatrixXd Problem::applyQ(const Eigen::MatrixXd& x) const {
  const Impl& p = *impl_;
  const Eigen::MatrixXd tx = p.mtx * x;
  const Eigen::MatrixXd w = p.ltt.solve(tx);
  Eigen::MatrixXd q = p.mxx * x;
  q.noalias() -= p.mxt * w;
  return q;
}

double Problem::objective(const Eigen::MatrixXd& x) const {
  return poseObjective(x, translations(x));
}

Eigen::MatrixXd Problem::objectiveAndProduct(const Eigen::MatrixXd& x, double* f) const {
  // From the residuals at the optimal translations, where tr(X^T Q X) would cancel large
  // terms: Q X = the rotation rows of M [T; X] (its translation rows vanish at T).
  const Eigen::MatrixXd t = translations(x);
  Eigen::MatrixXd qx = Eigen::MatrixXd::Zero(x.rows(), x.cols());
  double sum = 0.0;
  for (const Measurement& m : measurements_) {
    const auto xi = x.middleRows(d_ * m.i, d_);
    const Eigen::MatrixXd e = x.middleRows(d_ * m.j, d_) - m.rotation.transpose() * xi;
    const Eigen::RowVectorXd et = t.row(m.j) - t.row(m.i) - m.translation.transpose() * xi;
    sum += m.kappa * e.squaredNorm() + m.tau * et.squaredNorm();
    qx.middleRows(d_ * m.j, d_) += m.kappa * e;
    qx.middleRows(d_ * m.i, d_) -= m.kappa * m.rotation * e + m.tau * m.translation * et;
  }
  if (f) *f = sum;
  return qx;
}

Eigen::MatrixXd Problem::translations(const Eigen::MatrixXd& x) const {
  const Impl& p = *impl_;
  Eigen::MatrixXd t = Eigen::MatrixXd::Zero(n_, x.cols());
  const Eigen::MatrixXd rhs = -(p.mtx * x);
  t.bottomRows(n_ - 1) = p.ltt.solve(rhs);
  return t;
}

double Problem::poseObjective(const Eigen::MatrixXd& x, const Eigen::MatrixXd& t) const {
  double f = 0.0;
  for (const Measurement& m : measurements_) {
    const Eigen::MatrixXd ri = x.middleRows(d_ * m.i, d_).transpose();
    const Eigen::MatrixXd rj = x.middleRows(d_ * m.j, d_).transpose();
    const Eigen::VectorXd dt = t.row(m.j).transpose() - t.row(m.i).transpose() - ri * m.translation;
    f += m.kappa * (rj - ri * m.rotation).squaredNorm() + m.tau * dt.squaredNorm();
  }
  return f;
}

Eigen::MatrixXd Problem::denseQ() const {
  const Impl& p = *impl_;
  const Eigen::MatrixXd mtx = Eigen::MatrixXd(p.mtx);
  return Eigen::MatrixXd(p.mxx) - Eigen::MatrixXd(p.mxt) * p.ltt.solve(mtx);
}

bool ShiftedFactor::factorize(const Eigen::MatrixXd& lambda, double sigma) {
  const Problem::Impl& p = problem_->impl();
  const int d = problem_->dimension();
  const int n = problem_->numPoses();
  k_ = p.k;
  double* values = k_.valuePtr();
  for (int i = 0; i < n; ++i) {
    for (int a = 0; a < d; ++a) {
      for (int b = 0; b <= a; ++b) {
        double& v = values[p.block_entries[static_cast<std::size_t>(i * d * d + a * d + b)]];
        if (lambda.size() != 0) v -= lambda(a, d * i + b);
        if (a == b) v += sigma;
      }
    }
  }
  if (!analyzed_) {
    llt_.analyzePattern(k_);
    analyzed_ = true;
  }
  llt_.factorize(k_);
  return llt_.info() == Eigen::Success;
}

Eigen::MatrixXd ShiftedFactor::solve(const Eigen::MatrixXd& v) const {
  const int offset = problem_->numPoses() - 1;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(offset + v.rows(), v.cols());
  rhs.bottomRows(v.rows()) = v;
  return llt_.solve(rhs).bottomRows(v.rows());
}

}  // namespace graphslam::certify
