// SPDX-License-Identifier: MIT
// The default solver: picks the ordering and the backend from the predicted cost of the
// factorisation (symbolic analysis on the block graph).
#include <cstdio>
#include <functional>
#include <future>
#include <memory>
#include <numeric>
#include <optional>
#include <string>

#include "common.h"
#include "factories.h"
#include "graphslam/solvers/options.h"
#include "graphslam/solvers/ordering.h"
#include "graphslam/solvers/register.h"
#include "ordering.h"
#include "symbolic.h"
#ifdef GRAPHSLAM_HAVE_CHOLMOD
#include "suitesparse.h"
#endif

namespace graphslam::solvers {

namespace {

class AutoSolver final : public LinearSolver {
 public:
  /// The block orderings are kept in options.ordering_cache when it names one, else in a
  /// cache of the solver's own.
  explicit AutoSolver(const SolverOptions& options)
      : options_(options),
        ordering_cache_(options.ordering_cache
                            ? options.ordering_cache
                            : std::make_shared<OrderingCache>(options.ordering_cache_options)) {}

  /// The choice made at analysis, and the path of the last factorisation when it was the
  /// scalar (isotropic) or the complex (conformal) one.
  std::string name() const override {
    if (!analyzed_) return "auto";
    if (cost_.factor_nonzeros < 0) {
      // Not predicted at analysis (a small system): the backend's own analysis has the
      // figures once it factorised, else they are computed now.
      const std::optional<CholeskyPrediction> c =
          backend_ ? backend_->analysedCost() : std::nullopt;
      cost_ = c ? *c : predictCholesky(structure_, order_);
    }
    char buf[160];
    std::snprintf(buf, sizeof buf, "auto: %s:%s, predicted nnz(L) %.0f, %.3g flops", backend_name_,
                  toString(label_), cost_.factor_nonzeros, cost_.flops);
    std::string name = buf;
    if (active_ && path_) name += path_;
    return name;
  }
  Ordering ordering() const override { return analyzed_ ? label_ : Ordering::kDefault; }

  /// Systems factorised by supernodal CHOLMOD ask for H in the chosen order,
  /// postordered, as its lower triangle: CHOLMOD then factorises H's own arrays instead
  /// of a permuted copy made in every factorisation (as large as H itself).
  std::vector<int> preferredBlockOrder(const SparseStructure& s) override {
    planned_order_.clear();
    planned_for_ = {};
    if (s.lower) return {};
    const detail::BlockGraph g = detail::blockGraph(s);
    plan(s, g);
    planned_for_ = s;  // analyze() of this same structure keeps the plan
#ifdef GRAPHSLAM_HAVE_CHOLMOD
    if (plan_.supernodal) {
      planned_order_ = detail::postorderedBlocks(s, g, plan_.chosen.perm);
      return planned_order_;
    }
#endif
    return {};
  }

  LinearSolverResult analyze(const SparseStructure& s) override {
    const bool prepermuted = s.lower;
    if (prepermuted) {
      // H in the order preferredBlockOrder() gave: the plan made there stands.
      if (planned_order_.size() != static_cast<std::size_t>(s.num_blocks)) {
        return LinearSolverResult::failure(
            LinearSolverStatus::kFailure,
            "auto: H's lower triangle is taken only in the order preferredBlockOrder() gave");
      }
      plan_.chosen.perm.resize(static_cast<std::size_t>(s.n));
      std::iota(plan_.chosen.perm.begin(), plan_.chosen.perm.end(), 0);
    } else if (!samePattern(planned_for_, s)) {
      plan(s, detail::blockGraph(s));
    }
    planned_order_.clear();
    planned_for_ = {};
    const Ordering label = plan_.chosen.ordering;
    const char* backend = "eigen-ldlt";
    make_backend_ = [](Ordering) { return makeEigenLdlt(); };
    if (plan_.supernodal) {
#ifdef GRAPHSLAM_HAVE_CHOLMOD
      make_backend_ = [prepermuted, this](Ordering o) {
        return makeCholmodSolver(true, o, prepermuted, options_.cholmod);
      };
      backend = "cholmod";
#endif
    } else if (plan_.blocks) {
      make_backend_ = [this](Ordering o) { return makeBlockCholesky(o, options_.block_cholesky); };
      backend = "block-llt";
    }
    backend_name_ = backend;
    cost_ = plan_.chosen.prediction;
    structure_ = s;
    label_ = label;
    order_ = std::move(plan_.chosen.perm);
    backend_.reset();
    isotropic_.reset();
    conformal_.reset();
    active_ = nullptr;
    analyzed_ = true;
    // Vertices of one dimension d > 1: values of the form H_s (x) I_d take the scalar path,
    // and for d = 2 blocks [a -b; b a] the complex one.
    may_be_isotropic_ = s.num_blocks > 0 && s.block_starts[1] - s.block_starts[0] > 1 &&
                        maxBlockSize(s) == s.block_starts[1] - s.block_starts[0];
#ifdef GRAPHSLAM_HAVE_CHOLMOD
    may_be_conformal_ = may_be_isotropic_ && s.block_starts[1] - s.block_starts[0] == 2 &&
                        (plan_.supernodal || complexPathPays(s.n, plan_.chosen.prediction.flops));
#endif
    // Each path's own analysis (the backend's too) is made at its first factorisation:
    // a system that always takes the scalar or complex path never pays for the other.
    return LinearSolverResult::success();
  }

  LinearSolverResult factorize(const double* values) override {
    if (!analyzed_)
      return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not analysed");
    // H = H_s (x) I_d (linear SLAM with isotropic noise, the positions of the SE(2)
    // initial guess) is factorised as H_s: d^3 fewer flops. The test stops at the first
    // block that is not a multiple of I (at once for SE(2) poses).
    // Blocks [a -b; b a] (the orientations of the SE(2) initial guess) are a Hermitian
    // complex matrix: half the flops and half the memory of the 2x2 block factor.
    // Once the complex path was taken, the scalar one shares its analysis (one solver for
    // both: the SE(2) initial guess's orientation system, then its position system, of one
    // pattern); a system that only ever has isotropic values keeps the scalar path's own
    // choices (a dense tail's BLAS loop among them).
    active_ = nullptr;
    path_ = nullptr;
    const auto make_two_way = [this](Ordering o) { return makeTwoWayIsotropicSolver(o, options_); };
    if (may_be_isotropic_ && detail::firstNonIsotropicColumn(structure_, values) < 0) {
      if (conformal_) {
        path_ = " (isotropic path, on the complex path's analysis)";
        return factorizeWith(conformal_, make_two_way, values);
      }
      path_ = " (isotropic path)";
      return factorizeWith(
          isotropic_, [this](Ordering o) { return makeIsotropicSolver(o, options_); }, values);
    }
    if (may_be_conformal_ && detail::firstNonConformalColumn(structure_, values) < 0) {
      path_ = " (complex path)";
      return factorizeWith(conformal_, make_two_way, values);
    }
    return factorizeWith(backend_, make_backend_, values);
  }
  LinearSolverResult solve(const double* rhs, double* x) override {
    if (!active_)
      return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not factorised");
    return active_->solve(rhs, x);
  }
  std::size_t factorNonZeros() const override { return active_ ? active_->factorNonZeros() : 0; }
  bool factorPattern(std::vector<int>& col_ptr, std::vector<int>& row_idx) const override {
    return active_ && active_->factorPattern(col_ptr, row_idx);
  }

 private:
  /// Factorises with `solver`, made and analysed with auto's ordering on first use (the
  /// block or scalar backend, the isotropic or the conformal path).
  template <typename Make>
  LinearSolverResult factorizeWith(std::unique_ptr<detail::OrderedSolver>& solver, Make make,
                                   const double* values) {
    if (!solver) {
      solver = make(label_);
      const LinearSolverResult r = solver->analyzeOrdered(structure_, order_, label_);
      if (!r.ok()) {
        solver.reset();
        return r;
      }
    }
    active_ = solver.get();
    return solver->factorize(values);
  }

  /// The ordering and the backend chosen from H's pattern.
  struct Plan {
    ChosenOrdering chosen;
    bool blocks = false;      // block-llt: fixed-size block kernels
    bool supernodal = false;  // CHOLMOD's supernodal factorisation
  };
  /// Whether two structures are the same arrays (a plan made for one holds for the other).
  static bool samePattern(const SparseStructure& a, const SparseStructure& b) {
    return a.n > 0 && a.n == b.n && a.col_ptr == b.col_ptr && a.row_idx == b.row_idx &&
           a.block_starts == b.block_starts && a.num_blocks == b.num_blocks && a.lower == b.lower &&
           a.nnz() == b.nnz();
  }
  /// Whether the cost model predicts CHOLMOD's complex factorisation of a conformal system
  /// (n/2 complex unknowns; half the flops of its 2x2 block factor, `flops`, in real
  /// multiply-adds) faster than the backend chosen for the block system.
  [[nodiscard]] bool complexPathPays(int n, double flops) const {
    const CostModel& model = detail::costModel(options_.auto_solver);
    const FactorBackend chosen =
        plan_.blocks ? FactorBackend::kBlockLlt : FactorBackend::kEigenLdlt;
    const double complex_seconds =
        model.predict(FactorBackend::kCholmodSupernodal, 1, 0.5 * n, 0.5 * flops);
    return flops > 0.0 && complex_seconds < model.predict(chosen, 2, n, flops);
  }
  void plan(const SparseStructure& s, const detail::BlockGraph& g) {
    // Small systems are not predicted exactly here: name() asks the backend's analysis.
    plan_.chosen =
        detail::chooseOrdering(s, g, options_.auto_solver, ordering_cache_.get(), /*exact=*/false);
    // The backend the cost model predicts fastest for this system.
    const detail::BackendChoice c =
        detail::fastestBackend(detail::costModel(options_.auto_solver), maxBlockSize(s), s.n,
                               plan_.chosen.prediction.flops);
    plan_.blocks = c.backend == FactorBackend::kBlockLlt;
    plan_.supernodal = c.backend == FactorBackend::kCholmodSupernodal;
  }

  SolverOptions options_;
  std::shared_ptr<OrderingCache> ordering_cache_;  // never null
  const char* backend_name_ = "";
  mutable CholeskyPrediction cost_;  // factor_nonzeros < 0: not known yet (name())
  bool analyzed_ = false;
  Plan plan_;
  std::vector<int> planned_order_;  // the block order preferredBlockOrder() asked for
  SparseStructure planned_for_;     // the structure plan_ was made for (n = 0: none)
  // The backend (block-llt, eigen-ldlt or cholmod) and the scalar and complex paths for
  // isotropic and conformal values, each made and analysed at its first use with the
  // same ordering (conformal_ is a two-way solver, which takes the isotropic values too
  // once it exists); active_ is the one of the last factorisation.
  std::function<std::unique_ptr<detail::OrderedSolver>(Ordering)> make_backend_;
  std::unique_ptr<detail::OrderedSolver> backend_;
  SparseStructure structure_;
  Ordering label_ = Ordering::kDefault;
  std::vector<int> order_;
  bool may_be_isotropic_ = false;
  bool may_be_conformal_ = false;
  std::unique_ptr<detail::OrderedSolver> isotropic_, conformal_;
  LinearSolver* active_ = nullptr;
  const char* path_ = nullptr;  // the isotropic or the complex path when active_ is one
};

}  // namespace

std::vector<int> fillReducingOrdering(Ordering ordering, const SparseStructure& s,
                                      OrderingCache* cache) {
  return detail::orderColumns(ordering, s, cache);
}

CholeskyPrediction predictCholesky(const SparseStructure& s, const std::vector<int>& perm) {
  const detail::SymbolicCost c = detail::symbolicCost(s, perm);
  return {c.factor_nonzeros, c.flops};
}

ChosenOrdering chooseOrdering(const SparseStructure& s, const AutoSolverOptions& options) {
  return detail::chooseOrdering(s, detail::blockGraph(s), options, nullptr);
}

const CostModel& detail::costModel(const AutoSolverOptions& options) {
  return options.cost_model ? *options.cost_model : CostModel::builtIn();
}

detail::BackendChoice detail::fastestBackend(const CostModel& model, int block_size, double n,
                                             double flops) {
  BackendChoice best{FactorBackend::kEigenLdlt,
                     model.predict(FactorBackend::kEigenLdlt, block_size, n, flops)};
  const auto consider = [&](FactorBackend b) {
    const double seconds = model.predict(b, block_size, n, flops);
    if (seconds < best.seconds) best = {b, seconds};
  };
  if (block_size >= 1 && block_size <= 6) consider(FactorBackend::kBlockLlt);
#ifdef GRAPHSLAM_HAVE_CHOLMOD
  consider(FactorBackend::kCholmodSupernodal);
#endif
  return best;
}

// AMD always; METIS beside it when the cost model says the factorisations it may save pay
// for computing it (a small system never gets that far: AMD's own bound on the work decides
// without an exact prediction).
ChosenOrdering detail::chooseOrdering(const SparseStructure& s, const BlockGraph& g,
                                      const AutoSolverOptions& options, OrderingCache* cache,
                                      bool exact) {
  const CostModel& model = costModel(options);
  const int d = maxBlockSize(s);
  const auto seconds = [&](double flops) { return fastestBackend(model, d, s.n, flops).seconds; };
  auto predict = [&](const std::vector<int>& perm) {
    const detail::SymbolicCost c = detail::symbolicCost(s, g, perm);
    return CholeskyPrediction{c.factor_nonzeros, c.flops};
  };
  const double metis_seconds = model.metis.predict(g.num_blocks, static_cast<double>(g.idx.size()));
  ChosenOrdering chosen;
#ifdef GRAPHSLAM_HAVE_CHOLMOD
  auto metis = [&] {
    ChosenOrdering m;
    m.ordering = Ordering::kMetis;
    m.perm = detail::orderColumns(Ordering::kMetis, s, g, cache);
    m.prediction = predict(m.perm);
    return m;
  };
  // Graphs this large always need METIS as well: both orderings are serial codes, so they
  // run side by side.
  std::future<ChosenOrdering> metis_ahead;
  if (g.num_blocks >= options.concurrent_ordering_blocks) {
    metis_ahead = std::async(std::launch::async, metis);
  }
#endif
  double amd_work = -1.0;
  chosen.perm = detail::orderColumnsAmd(s, g, &amd_work, cache);
  // d^3 sum_j (b_j + 1)^2 bounds the scalar flops (b_j: blocks below the diagonal in
  // block column j, d: the largest block).
  const double bound = static_cast<double>(d) * d * d * amd_work;
  const bool metis_may_pay = options.expected_factorizations * seconds(bound) > metis_seconds;
  if (!exact && amd_work >= 0.0 && !metis_may_pay) {
    chosen.prediction = {-1.0, bound};
    return chosen;
  }
  chosen.prediction = predict(chosen.perm);
#ifdef GRAPHSLAM_HAVE_CHOLMOD
  if (metis_ahead.valid() ||
      options.expected_factorizations * seconds(chosen.prediction.flops) > metis_seconds) {
    ChosenOrdering m = metis_ahead.valid() ? metis_ahead.get() : metis();
    if (seconds(m.prediction.flops) < seconds(chosen.prediction.flops)) chosen = std::move(m);
  }
#else
  static_cast<void>(metis_seconds);
#endif
  return chosen;
}

void registerAutoSolver(SolverRegistry& registry, const SolverOptions& options) {
  registry.registerSolver("auto",
                          "the default: orders H by AMD, or METIS when it pays, and factorises "
                          "with the backend its cost model predicts fastest (block-llt, "
                          "eigen-ldlt or supernodal cholmod; graphslam calibrate measures it)",
                          [options] { return std::make_unique<AutoSolver>(options); });
}

}  // namespace graphslam::solvers
