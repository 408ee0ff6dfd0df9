// SPDX-License-Identifier: MIT
#include "graphslam/solvers/cost_model.h"

#include <Eigen/Dense>
#include <algorithm>
#include <limits>
#include <istream>
#include <ostream>
#include <set>
#include <sstream>

#include "graphslam/support/error.h"
#include "graphslam/support/file_util.h"

namespace graphslam::solvers {

namespace {

// The built-in calibration (solvers/calibration.txt), put here by CMake.
constexpr const char* kBuiltInCalibration =
#include "calibration_text.inc"
    ;

/// The line of `name` ("block-llt-3", "eigen-ldlt", ...) in `model`, or null.
CostLine* lineOf(CostModel& model, const std::string& name) {
  if (name == "block-llt-1") return &model.block_llt[0];
  if (name == "block-llt-2") return &model.block_llt[1];
  if (name == "block-llt-3") return &model.block_llt[2];
  if (name == "block-llt-6") return &model.block_llt[3];
  if (name == "eigen-ldlt") return &model.eigen_ldlt;
  if (name == "cholmod-supernodal") return &model.cholmod_supernodal;
  if (name == "metis") return &model.metis;
  return nullptr;
}

constexpr const char* kLineNames[] = {"block-llt-1", "block-llt-2", "block-llt-3", "block-llt-6",
                                      "eigen-ldlt",  "cholmod-supernodal", "metis"};

}  // namespace

const char* toString(FactorBackend backend) {
  switch (backend) {
    case FactorBackend::kBlockLlt:
      return "block-llt";
    case FactorBackend::kEigenLdlt:
      return "eigen-ldlt";
    case FactorBackend::kCholmodSupernodal:
      return "cholmod";
  }
  return "?";
}

int CostModel::blockClass(int block_size) {
  return std::clamp(block_size, 1, 4) - 1;
}

double CostModel::predict(FactorBackend backend, int block_size, double n, double flops) const {
  switch (backend) {
    case FactorBackend::kBlockLlt:
      return block_llt[blockClass(block_size)].predict(n, flops);
    case FactorBackend::kEigenLdlt:
      return eigen_ldlt.predict(n, flops);
    case FactorBackend::kCholmodSupernodal:
      return cholmod_supernodal.predict(n, flops);
  }
  return 0.0;
}

const CostModel& CostModel::builtIn() {
  static const CostModel model = [] {
    std::istringstream in(kBuiltInCalibration);
    return read(in, "solvers/calibration.txt (built in)");
  }();
  return model;
}

// Lines "NAME seconds per_unknown per_flop"; "# " lines are comments, the first of which
// describes the calibration (source). Every name must appear once.
CostModel CostModel::read(std::istream& in, const std::string& name) {
  CostModel model;
  std::string line;
  int line_no = 0;
  int seen = 0;
  std::set<std::string> names;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty()) continue;
    if (line[0] == '#') {
      if (model.source.empty() && line.size() > 2) model.source = line.substr(2);
      continue;
    }
    std::istringstream fields(line);
    std::string key;
    CostLine value;
    fields >> key >> value.seconds >> value.per_unknown >> value.per_flop;
    CostLine* target = lineOf(model, key);
    std::string rest;
    if (!fields || (fields >> rest) || !target || value.seconds < 0 || value.per_unknown < 0 ||
        value.per_flop < 0) {
      throw InputError(name + ":" + std::to_string(line_no) +
                       ": expected NAME SECONDS PER_UNKNOWN PER_FLOP (non-negative numbers; "
                       "NAME one of block-llt-1, -2, -3, -6, eigen-ldlt, cholmod-supernodal, "
                       "metis)");
    }
    if (!names.insert(key).second) {
      throw InputError(name + ":" + std::to_string(line_no) + ": " + key + " given twice");
    }
    *target = value;
    ++seen;
  }
  if (seen != static_cast<int>(std::size(kLineNames))) {
    throw InputError(name + ": expected " + std::to_string(std::size(kLineNames)) +
                     " lines of constants, found " + std::to_string(seen));
  }
  return model;
}

void CostModel::write(std::ostream& out) const {
  out << "# " << source << "\n"
      << "# NAME seconds per_unknown per_flop (seconds of one factorisation = seconds + "
         "per_unknown n + per_flop flops; metis: blocks and non-zero blocks of H)\n";
  CostModel copy = *this;
  for (const char* key : kLineNames) {
    const CostLine& l = *lineOf(copy, key);
    out << key << ' ' << support::formatDouble(l.seconds) << ' '
        << support::formatDouble(l.per_unknown) << ' ' << support::formatDouble(l.per_flop)
        << "\n";
  }
}

namespace {

/// The non-negative least-squares fit of one line (relative errors).
CostLine fitLine(const std::vector<const CostSample*>& rows) {
  CostLine best;
  double best_error = std::numeric_limits<double>::infinity();
  for (int terms = 1; terms < 8; ++terms) {  // bits: constant, per unknown, per flop
    std::vector<int> used;
    for (int k = 0; k < 3; ++k) {
      if (terms & (1 << k)) used.push_back(k);
    }
    Eigen::MatrixXd a(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(used.size()));
    Eigen::VectorXd b = Eigen::VectorXd::Ones(static_cast<Eigen::Index>(rows.size()));
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const double feature[3] = {1.0, rows[i]->n, rows[i]->flops};
      for (std::size_t j = 0; j < used.size(); ++j) {
        a(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) =
            feature[used[j]] / rows[i]->seconds;
      }
    }
    const Eigen::VectorXd x = a.colPivHouseholderQr().solve(b);
    if ((x.array() < 0.0).any() || !x.allFinite()) continue;
    const double error = (a * x - b).squaredNorm();
    if (error < best_error) {
      best_error = error;
      best = {};
      double* coefficient[3] = {&best.seconds, &best.per_unknown, &best.per_flop};
      for (std::size_t j = 0; j < used.size(); ++j) *coefficient[used[j]] = x[static_cast<Eigen::Index>(j)];
    }
  }
  return best;
}

}  // namespace

CostModel fitCostModel(const std::vector<CostSample>& samples, std::string source) {
  CostModel model;
  model.source = std::move(source);
  for (const char* key : kLineNames) {
    std::vector<const CostSample*> rows;
    for (const auto& s : samples) {
      if (s.line == key && s.seconds > 0.0) rows.push_back(&s);
    }
    if (rows.empty()) throw Error(std::string("no measurement of ") + key + " to fit");
    *lineOf(model, key) = fitLine(rows);
  }
  return model;
}

}  // namespace graphslam::solvers
