// SPDX-License-Identifier: MIT
#include "graphslam/submap/mpi_solver.h"

#include <mpi.h>

#include <chrono>
#include <cmath>
#include <limits>

#include "engine.h"
#include "graphslam/support/error.h"
#include "separator_system.h"

namespace graphslam::submap {
namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

int checkedCount(std::size_t n) {
  if (n > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    throw Error("submaps (MPI): a message of " + std::to_string(n) +
                " doubles is over MPI's count limit: use more ranks or submaps");
  }
  return static_cast<int>(n);
}

/// Doubles a submap's contribution takes on the wire: ok, max diagonal, |g_I|^2, the
/// upper triangle of the Schur complement, the reduced and the plain separator gradient.
std::size_t contributionSize(const Submap& s) {
  const auto d = static_cast<std::size_t>(s.separator_dimension);
  return 3 + d * (d + 1) / 2 + 2 * d;
}

void pack(const detail::Contribution& c, std::size_t d, std::vector<double>& out) {
  out.push_back(c.ok ? 1.0 : 0.0);
  out.push_back(c.max_diagonal);
  out.push_back(c.interior_gradient_squared);
  for (std::size_t j = 0; j < d; ++j) {
    for (std::size_t i = 0; i <= j; ++i) {
      out.push_back(c.ok ? c.schur(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j))
                         : 0.0);
    }
  }
  for (std::size_t i = 0; i < d; ++i)
    out.push_back(c.ok ? c.reduced[static_cast<Eigen::Index>(i)] : 0.0);
  for (std::size_t i = 0; i < d; ++i) out.push_back(c.gradient[static_cast<Eigen::Index>(i)]);
}

detail::Contribution unpack(const double* in, std::size_t d) {
  detail::Contribution c;
  const auto n = static_cast<Eigen::Index>(d);
  c.ok = in[0] != 0.0;
  c.max_diagonal = in[1];
  c.interior_gradient_squared = in[2];
  in += 3;
  c.schur.resize(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::Index i = 0; i <= j; ++i) c.schur(i, j) = c.schur(j, i) = *in++;
  }
  c.reduced = Eigen::Map<const Eigen::VectorXd>(in, n);
  c.gradient = Eigen::Map<const Eigen::VectorXd>(in + n, n);
  return c;
}

/// Where each rank's block starts in a gathered buffer: rank r sends its submaps r, r +
/// ranks, ... back to back, submap k taking sizes[k] doubles; one more entry: the total.
std::vector<std::size_t> rankOffsets(const std::vector<std::size_t>& sizes, int ranks) {
  std::vector<std::size_t> at(static_cast<std::size_t>(ranks) + 1, 0);
  for (std::size_t k = 0; k < sizes.size(); ++k)
    at[k % static_cast<std::size_t>(ranks) + 1] += sizes[k];
  for (std::size_t r = 1; r < at.size(); ++r) at[r] += at[r - 1];
  return at;
}

std::vector<int> submapsOfRank(const Partition& p, int rank, int size) {
  std::vector<int> mine;
  for (int k = rank; k < static_cast<int>(p.submaps.size()); k += size) mine.push_back(k);
  return mine;
}

/// The submaps of this rank; the separator system on rank 0.
class MpiEngine final : public detail::Engine {
 public:
  MpiEngine(const Partition& partition, const Options& options, int rank, int size)
      : partition_(partition),
        rank_(rank),
        size_(size),
        mine_(submapsOfRank(partition, rank, size)),
        submaps_(partition, mine_, options.threads, options.keep_factorizations,
                 options.supernodal_interiors),
        separator_(partition, options, rank == 0),
        estimates_(partition) {}

  detail::Cost cost() override {
    // One entry per submap, set by its rank alone: the sums are exact in any order.
    std::vector<double> all(2 * partition_.submaps.size(), 0.0);
    const auto local = submaps_.costs();
    for (std::size_t k = 0; k < mine_.size(); ++k) {
      all[2 * static_cast<std::size_t>(mine_[k])] = local[k].first;
      all[2 * static_cast<std::size_t>(mine_[k]) + 1] = local[k].second;
    }
    allReduce(all);
    detail::Cost sum{0.0, 0.0};
    for (std::size_t k = 0; k < partition_.submaps.size(); ++k) {
      sum.first += all[2 * k];
      sum.second += all[2 * k + 1];
    }
    return sum;
  }

  void linearize() override { submaps_.linearize(); }

  detail::StepOutcome step(double lambda) override;

  void undo() override {
    submaps_.restore();
    estimates_.restore();
  }

  double gradientNorm() override {
    std::vector<double> send;
    for (const auto& c : submaps_.gradients()) {
      send.push_back(c.interior_gradient_squared);
      send.insert(send.end(), c.gradient.data(), c.gradient.data() + c.gradient.size());
    }
    gatherToRoot(send, /*gradient_only=*/true);
    double norm = 0.0;
    if (rank_ == 0) norm = std::sqrt(interior_squared_ + separator_.gradientSquared());
    broadcast(&norm, 1);
    return norm;
  }

  std::size_t takeBytes() override {
    unsigned long long mine = bytes_, total = 0;
    MPI_Allreduce(&mine, &total, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
    bytes_ = 0;
    return static_cast<std::size_t>(total);
  }

  /// Rank 0 receives every rank's interior estimates.
  void gatherEstimates();

 private:
  void allReduce(std::vector<double>& v) {
    MPI_Allreduce(MPI_IN_PLACE, v.data(), checkedCount(v.size()), MPI_DOUBLE, MPI_SUM,
                  MPI_COMM_WORLD);
    bytes_ += v.size() * sizeof(double);
  }
  void broadcast(double* data, std::size_t n) {
    MPI_Bcast(data, checkedCount(n), MPI_DOUBLE, 0, MPI_COMM_WORLD);
    if (rank_ == 0) bytes_ += n * sizeof(double) * static_cast<std::size_t>(size_ - 1);
  }
  /// Sends this rank's contributions to rank 0, which adds them to the separator system
  /// in submap order (and sums |g_I|^2 and the largest diagonal entry). Returns on rank 0
  /// the first submap whose interior did not factorise (-1 when none).
  int gatherToRoot(const std::vector<double>& send, bool gradient_only);
  std::vector<double> gatherv(const std::vector<double>& send,
                              const std::vector<std::size_t>& submap_sizes);

  const Partition& partition_;
  int rank_, size_;
  std::vector<int> mine_;
  detail::LocalSubmaps submaps_;
  detail::SeparatorSystem separator_;
  detail::SeparatorEstimates estimates_;
  double interior_squared_ = 0.0, max_diagonal_ = 0.0;
  std::size_t bytes_ = 0;
};

std::vector<double> MpiEngine::gatherv(const std::vector<double>& send,
                                       const std::vector<std::size_t>& submap_sizes) {
  const std::vector<std::size_t> at = rankOffsets(submap_sizes, size_);
  std::vector<int> counts(static_cast<std::size_t>(size_)), displs(counts.size());
  for (std::size_t r = 0; r < counts.size(); ++r) {
    displs[r] = checkedCount(at[r]);
    counts[r] = checkedCount(at[r + 1] - at[r]);
  }
  const std::size_t total = at.back();
  std::vector<double> recv(rank_ == 0 ? total : 0);
  MPI_Gatherv(send.data(), checkedCount(send.size()), MPI_DOUBLE, recv.data(), counts.data(),
              displs.data(), MPI_DOUBLE, 0, MPI_COMM_WORLD);
  if (rank_ != 0) bytes_ += send.size() * sizeof(double);
  return recv;
}

int MpiEngine::gatherToRoot(const std::vector<double>& send, bool gradient_only) {
  std::vector<std::size_t> sizes;
  for (const Submap& s : partition_.submaps) {
    const auto d = static_cast<std::size_t>(s.separator_dimension);
    sizes.push_back(gradient_only ? 1 + d : contributionSize(s));
  }
  const std::vector<double> recv = gatherv(send, sizes);
  if (rank_ != 0) return -1;
  std::vector<std::size_t> at = rankOffsets(sizes, size_);
  separator_.clear();
  interior_squared_ = max_diagonal_ = 0.0;
  int failed = -1;
  for (std::size_t k = 0; k < sizes.size(); ++k) {
    const double* in = recv.data() + at[k % static_cast<std::size_t>(size_)];
    at[k % static_cast<std::size_t>(size_)] += sizes[k];
    const auto d = static_cast<std::size_t>(partition_.submaps[k].separator_dimension);
    detail::Contribution c;
    if (gradient_only) {
      c.interior_gradient_squared = in[0];
      c.gradient = Eigen::Map<const Eigen::VectorXd>(in + 1, static_cast<Eigen::Index>(d));
      c.schur.setZero(static_cast<Eigen::Index>(d), static_cast<Eigen::Index>(d));
      c.reduced.setZero(static_cast<Eigen::Index>(d));
    } else {
      c = unpack(in, d);
    }
    interior_squared_ += c.interior_gradient_squared;
    max_diagonal_ = std::max(max_diagonal_, c.max_diagonal);
    if (!c.ok && failed < 0) failed = static_cast<int>(k);
    if (c.ok) separator_.add(static_cast<int>(k), c);
  }
  return failed;
}

detail::StepOutcome MpiEngine::step(double lambda) {
  detail::StepOutcome out;
  auto t = Clock::now();
  std::vector<double> send;
  submaps_.eliminate(lambda, [&](std::size_t k, detail::Contribution& c) {
    pack(c, static_cast<std::size_t>(submaps_.systems()[k].submap().separator_dimension), send);
  });
  const int failed = gatherToRoot(send, false);
  out.time_eliminate = secondsSince(t);
  t = Clock::now();
  // Rank 0 broadcasts: ok, the failed submap, gradient norm, largest diagonal, nonzeros,
  // conjugate-gradient iterations, dx_S.
  const auto ns = static_cast<std::size_t>(partition_.separator_offsets.back());
  std::vector<double> reply(6 + ns, 0.0);
  if (rank_ == 0) {
    Eigen::VectorXd dx;
    bool ok = failed < 0 && separator_.solve(lambda, dx, out.message);
    reply[0] = ok ? 1.0 : 0.0;
    reply[1] = failed;
    reply[2] = std::sqrt(interior_squared_ + separator_.gradientSquared());
    reply[3] = max_diagonal_;
    reply[4] = static_cast<double>(separator_.nonzeros());
    reply[5] = separator_.iterations();
    if (ok) std::copy(dx.data(), dx.data() + ns, reply.begin() + 6);
  }
  broadcast(reply.data(), reply.size());
  out.gradient_norm = reply[2];
  out.max_diagonal = reply[3];
  out.separator_nonzeros = static_cast<std::size_t>(reply[4]);
  out.separator_iterations = static_cast<int>(reply[5]);
  out.time_separator = secondsSince(t);
  if (reply[0] == 0.0) {
    out.ok = false;
    if (reply[1] >= 0) {
      out.message = "submap " + std::to_string(static_cast<int>(reply[1])) +
                    ": its interior system is not positive definite (on rank " +
                    std::to_string(static_cast<int>(reply[1]) % size_) + ")";
    } else if (out.message.empty()) {
      out.message =
          "the separator system was not solved (not positive definite, or its conjugate gradients "
          "did not converge)";
    }
    return out;
  }
  t = Clock::now();
  const Eigen::VectorXd dx_s =
      Eigen::Map<const Eigen::VectorXd>(reply.data() + 6, static_cast<Eigen::Index>(ns));
  double squared = 0.0;
  std::string message;
  std::vector<double> flags(static_cast<std::size_t>(size_) + 1, 0.0);
  const bool ok = submaps_.backSubstituteAndApply(dx_s, lambda, squared, message);
  flags[static_cast<std::size_t>(rank_)] = ok ? 0.0 : 1.0;
  flags.back() = squared;  // summed over ranks
  allReduce(flags);
  bool all_ok = true;
  for (int r = 0; r < size_; ++r) all_ok = all_ok && flags[static_cast<std::size_t>(r)] == 0.0;
  if (!all_ok) {
    if (ok) submaps_.restore();
    out.ok = false;
    out.message = ok ? "back-substitution failed on another rank" : message;
    return out;
  }
  estimates_.apply(dx_s);
  out.step_norm = std::sqrt(flags.back() + dx_s.squaredNorm());
  out.time_back = secondsSince(t);
  return out;
}

void MpiEngine::gatherEstimates() {
  std::vector<std::size_t> sizes;
  for (const Submap& s : partition_.submaps) {
    std::size_t n = 0;
    for (const Vertex* v : s.interior) n += static_cast<std::size_t>(v->estimateDataDimension());
    sizes.push_back(n);
  }
  std::vector<double> send;
  for (auto& system : submaps_.systems()) {
    const auto x = system.interiorEstimates();
    send.insert(send.end(), x.begin(), x.end());
  }
  const std::vector<double> recv = gatherv(send, sizes);
  if (rank_ != 0) return;
  std::vector<std::size_t> at = rankOffsets(sizes, size_);
  for (std::size_t k = 0; k < sizes.size(); ++k) {
    const double* in = recv.data() + at[k % static_cast<std::size_t>(size_)];
    at[k % static_cast<std::size_t>(size_)] += sizes[k];
    for (Vertex* v : partition_.submaps[k].interior) {
      v->setEstimateData(in);
      in += v->estimateDataDimension();
    }
  }
}

}  // namespace

MpiSession::MpiSession(int& argc, char**& argv) {
  MPI_Init(&argc, &argv);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiSession::~MpiSession() { MPI_Finalize(); }

MpiSubmapSolver::MpiSubmapSolver(Graph& graph, Options options)
    : graph_(graph), options_(std::move(options)) {}

Summary MpiSubmapSolver::optimize() {
  const auto start = Clock::now();
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  detail::GaugeFix gauge(graph_, options_.fix_gauge);
  const Partition partition = partitionGraph(graph_, options_.partition);
  MpiEngine engine(partition, options_, rank, size);
  Options options = options_;
  if (rank != 0) options.callback = nullptr;  // progress is rank 0's to report
  Summary summary = detail::runIterations(engine, partition, options);
  engine.gatherEstimates();
  summary.bytes_communicated += engine.takeBytes();
  summary.gauge_fixed = gauge.ids();
  summary.total_time = secondsSince(start);
  return summary;
}

}  // namespace graphslam::submap
