// SPDX-License-Identifier: MIT
// The factorisation cost model of the "auto" solver: one model of every backend it chooses
// among, whose constants are measured on the machine by `graphslam calibrate` (the built-in
// ones by the command on the development machine; solvers/calibration.txt), not typed in.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

namespace graphslam::solvers {

/// The backends "auto" chooses among.
enum class FactorBackend { kBlockLlt, kEigenLdlt, kCholmodSupernodal };

[[nodiscard]] const char* toString(FactorBackend backend);

/// Seconds of one numeric factorisation: seconds + per_unknown n + per_flop flops, n the
/// system's dimension and flops the symbolic prediction (sum of the squared column counts
/// of L).
struct CostLine {
  double seconds = 0.0;
  double per_unknown = 0.0;
  double per_flop = 0.0;
  [[nodiscard]] double predict(double n, double flops) const {
    return seconds + per_unknown * n + per_flop * flops;
  }
};

/// One line per backend and block size (block-llt's kernels differ per size), and one for
/// the METIS ordering (seconds + per_unknown blocks + per_flop non-zero blocks of H).
struct CostModel {
  /// block-llt on 1x1, 2x2, 3x3 and 4x4-6x6 blocks (blockClass).
  CostLine block_llt[4];
  CostLine eigen_ldlt;
  CostLine cholmod_supernodal;
  CostLine metis;
  /// Where the constants come from (the calibration's own description line).
  std::string source;

  /// Predicted seconds of `backend` on a system of dimension n with `block_size` the
  /// largest vertex dimension.
  [[nodiscard]] double predict(FactorBackend backend, int block_size, double n,
                               double flops) const;
  /// The index into block_llt of a block size: 1 -> 0, 2 -> 1, 3 -> 2, 4-6 -> 3.
  [[nodiscard]] static int blockClass(int block_size);

  /// The model measured on the development machine (solvers/calibration.txt, built in).
  [[nodiscard]] static const CostModel& builtIn();
  /// Reads a calibration file (`graphslam calibrate -o FILE`). Throws graphslam::InputError
  /// naming the file and line for anything it cannot use.
  [[nodiscard]] static CostModel read(std::istream& in, const std::string& name);
  /// Writes the model in the calibration file's format.
  void write(std::ostream& out) const;
};

/// One measured factorisation (or METIS ordering) for fitting a model: the line it belongs
/// to ("block-llt-3", ..., "metis"), the system's dimension n (METIS: blocks), its flops
/// (METIS: non-zero blocks of H) and the measured seconds.
struct CostSample {
  std::string line;
  double n = 0.0;
  double flops = 0.0;
  double seconds = 0.0;
};

/// The model fitted to `samples`: per line, the non-negative constants that minimise the
/// relative error of the predictions (least squares on seconds / measured over every
/// subset of the three terms, the best whose coefficients are all non-negative). Throws
/// graphslam::Error when a line has no sample.
[[nodiscard]] CostModel fitCostModel(const std::vector<CostSample>& samples, std::string source);

}  // namespace graphslam::solvers
