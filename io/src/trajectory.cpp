// SPDX-License-Identifier: MIT
#include "graphslam/io/trajectory.h"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <fstream>
#include <istream>
#include <ostream>
#include <sstream>
#include <string_view>
#include <system_error>

#include "graphslam/io/text_tokens.h"
#include "graphslam/support/file_util.h"

namespace graphslam::io {
namespace {

/// Splits a line into whitespace-separated tokens; everything from '#' on is a comment.
std::vector<std::string_view> tokenize(std::string_view line) {
  const std::size_t hash = line.find('#');
  if (hash != std::string_view::npos) line = line.substr(0, hash);
  std::vector<std::string_view> tokens;
  std::size_t i = 0;
  const auto is_space = [](char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
  };
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !is_space(line[i])) ++i;
    if (i > start) tokens.push_back(line.substr(start, i - start));
  }
  return tokens;
}

[[noreturn]] void fail(const std::string& source, std::size_t line_no, const std::string& what) {
  throw InputError(source + ":" + std::to_string(line_no) + ": " + what);
}

/// Parses one token as a finite double (locale independent); throws InputError.
double parseNumber(std::string_view token, const std::string& source, std::size_t line_no,
                   std::size_t column) {
  std::string_view digits = token;
  if (digits.size() > 1 && digits.front() == '+') digits.remove_prefix(1);
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  const std::string where = "token " + std::to_string(column + 1) + " " + io::quote(token);
  if (ec == std::errc::result_out_of_range)
    fail(source, line_no, where + " is out of the range of a double");
  if (ec != std::errc() || ptr != digits.data() + digits.size()) {
    fail(source, line_no, where + " is not a number");
  }
  if (!std::isfinite(value)) fail(source, line_no, where + " is not finite (NaN/Inf)");
  return value;
}

/// Reads every non-empty line of `in` and hands its numbers to `on_row`.
template <typename OnRow>
void forEachNumericLine(std::istream& in, const std::string& source, OnRow&& on_row) {
  std::string line;
  std::size_t line_no = 0;
  while (true) {
    const support::LineRead read = support::readBoundedLine(in, line, support::kMaxTextLineBytes);
    if (read == support::LineRead::kEnd) break;
    ++line_no;
    if (read == support::LineRead::kTooLong) {
      fail(source, line_no,
           "the line is longer than " + std::to_string(support::kMaxTextLineBytes) +
               " bytes: not a line of numbers");
    }
    const auto tokens = tokenize(line);
    if (tokens.empty()) continue;
    std::vector<double> values(tokens.size());
    for (std::size_t i = 0; i < tokens.size(); ++i) {
      values[i] = parseNumber(tokens[i], source, line_no, i);
    }
    on_row(values, line_no);
  }
  if (in.bad()) throw InputError(source + ": read error");
}

std::ifstream openForReading(const std::string& path) {
  errno = 0;
  std::ifstream in(path);
  if (!in) throw InputError(support::cannotOpenMessage(path, errno));
  return in;
}

/// Shortest decimal representation that reads back to the same double.
std::string formatNumber(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

void writeToFile(const std::string& path, const Trajectory& trajectory,
                 void (*writer)(std::ostream&, const Trajectory&)) {
  std::ofstream out(path);
  if (!out) throw Error(path + ": cannot open file for writing");
  writer(out, trajectory);
  out.flush();
  if (!out) throw Error(path + ": write failed");
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Trajectory

Trajectory::Trajectory(std::vector<double> timestamps, std::vector<Eigen::Isometry3d> poses)
    : timestamps_(std::move(timestamps)), poses_(std::move(poses)) {
  if (timestamps_.size() != poses_.size()) {
    throw Error("Trajectory: " + std::to_string(timestamps_.size()) + " timestamps but " +
                std::to_string(poses_.size()) + " poses");
  }
}

void Trajectory::append(double t, const Eigen::Isometry3d& pose) {
  timestamps_.push_back(t);
  poses_.push_back(pose);
}

Eigen::Matrix3Xd Trajectory::positions() const {
  Eigen::Matrix3Xd p(3, static_cast<Eigen::Index>(poses_.size()));
  for (std::size_t i = 0; i < poses_.size(); ++i) {
    p.col(static_cast<Eigen::Index>(i)) = poses_[i].translation();
  }
  return p;
}

Trajectory Trajectory::subset(const std::vector<std::size_t>& ids) const {
  Trajectory out;
  out.timestamps_.reserve(ids.size());
  out.poses_.reserve(ids.size());
  for (const std::size_t id : ids) out.append(timestamps_.at(id), poses_.at(id));
  return out;
}

double Trajectory::pathLength() const {
  double length = 0.0;
  for (std::size_t i = 1; i < poses_.size(); ++i) {
    length += (poses_[i].translation() - poses_[i - 1].translation()).norm();
  }
  return length;
}

void Trajectory::transform(const Eigen::Isometry3d& t, bool right_mul) {
  for (auto& pose : poses_)
    pose = right_mul ? Eigen::Isometry3d(pose * t) : Eigen::Isometry3d(t * pose);
}

void Trajectory::scale(double s) {
  for (auto& pose : poses_) pose.translation() *= s;
}

// ---------------------------------------------------------------------------------------
// TUM

Trajectory readTum(std::istream& in, const std::string& source_name) {
  Trajectory trajectory;
  forEachNumericLine(in, source_name, [&](const std::vector<double>& v, std::size_t line_no) {
    if (v.size() != 8) {
      fail(source_name, line_no,
           "expected 8 values 't x y z qx qy qz qw', got " + std::to_string(v.size()));
    }
    const Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);  // (w, x, y, z)
    const double norm = q.norm();
    if (!(std::abs(norm - 1.0) <= kQuaternionNormTolerance)) {
      fail(source_name, line_no,
           "quaternion norm " + formatNumber(norm) + " is not 1 (tolerance " +
               formatNumber(kQuaternionNormTolerance) + ")");
    }
    if (trajectory.size() > 0 && !(v[0] > trajectory.timestamps().back())) {
      fail(source_name, line_no,
           "timestamp " + formatNumber(v[0]) + " is not after the previous pose's (" +
               formatNumber(trajectory.timestamps().back()) +
               "): TUM poses must be in strictly increasing time");
    }
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = q.normalized().toRotationMatrix();
    pose.translation() = Eigen::Vector3d(v[1], v[2], v[3]);
    trajectory.append(v[0], pose);
  });
  return trajectory;
}

Trajectory readTum(const std::string& path) {
  auto in = openForReading(path);
  return readTum(in, path);
}

void writeTum(std::ostream& out, const Trajectory& trajectory) {
  for (std::size_t i = 0; i < trajectory.size(); ++i) {
    const Eigen::Isometry3d& pose = trajectory.pose(i);
    Eigen::Quaterniond q(pose.rotation());
    q.normalize();
    if (q.w() < 0.0) q.coeffs() = -q.coeffs();
    const Eigen::Vector3d t = pose.translation();
    out << formatNumber(trajectory.timestamp(i)) << ' ' << formatNumber(t.x()) << ' '
        << formatNumber(t.y()) << ' ' << formatNumber(t.z()) << ' ' << formatNumber(q.x()) << ' '
        << formatNumber(q.y()) << ' ' << formatNumber(q.z()) << ' ' << formatNumber(q.w()) << '\n';
  }
}

void writeTum(const std::string& path, const Trajectory& trajectory) {
  writeToFile(path, trajectory, static_cast<void (*)(std::ostream&, const Trajectory&)>(&writeTum));
}

// ---------------------------------------------------------------------------------------
// KITTI

Trajectory readKitti(std::istream& in, const std::string& source_name) {
  Trajectory trajectory;
  forEachNumericLine(in, source_name, [&](const std::vector<double>& v, std::size_t line_no) {
    if (v.size() != 12) {
      fail(source_name, line_no,
           "expected 12 values (3x4 row-major [R|t]), got " + std::to_string(v.size()));
    }
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) pose.matrix()(r, c) = v[static_cast<std::size_t>(4 * r + c)];
      pose.matrix()(r, 3) = v[static_cast<std::size_t>(4 * r + 3)];
    }
    const Eigen::Matrix3d rotation = pose.linear();
    const double orthogonality =
        (rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
    if (!(orthogonality <= kRotationTolerance) || rotation.determinant() <= 0.0) {
      fail(source_name, line_no,
           "rotation block is not a rotation matrix (max |R^T R - I| = " +
               formatNumber(orthogonality) + ", det = " + formatNumber(rotation.determinant()) +
               ")");
    }
    trajectory.append(static_cast<double>(trajectory.size()), pose);
  });
  return trajectory;
}

Trajectory readKitti(const std::string& path) {
  auto in = openForReading(path);
  return readKitti(in, path);
}

void writeKitti(std::ostream& out, const Trajectory& trajectory) {
  for (const Eigen::Isometry3d& pose : trajectory.poses()) {
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) {
        if (r != 0 || c != 0) out << ' ';
        out << formatNumber(pose.matrix()(r, c));
      }
    }
    out << '\n';
  }
}

void writeKitti(const std::string& path, const Trajectory& trajectory) {
  writeToFile(path, trajectory,
              static_cast<void (*)(std::ostream&, const Trajectory&)>(&writeKitti));
}

// ---------------------------------------------------------------------------------------
// Planar helpers

Eigen::Isometry3d se2ToIsometry3(double x, double y, double theta) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(x, y, 0.0);
  return pose;
}

Trajectory trajectoryFromSE2(const Eigen::Matrix3Xd& poses, const std::vector<double>& timestamps) {
  if (static_cast<std::size_t>(poses.cols()) != timestamps.size()) {
    throw Error("trajectoryFromSE2: " + std::to_string(poses.cols()) + " poses but " +
                std::to_string(timestamps.size()) + " timestamps");
  }
  Trajectory trajectory;
  for (Eigen::Index i = 0; i < poses.cols(); ++i) {
    trajectory.append(timestamps[static_cast<std::size_t>(i)],
                      se2ToIsometry3(poses(0, i), poses(1, i), poses(2, i)));
  }
  return trajectory;
}

Trajectory trajectoryFromSE2(const Eigen::Matrix3Xd& poses) {
  std::vector<double> timestamps(static_cast<std::size_t>(poses.cols()));
  for (std::size_t i = 0; i < timestamps.size(); ++i) timestamps[i] = static_cast<double>(i);
  return trajectoryFromSE2(poses, timestamps);
}

Eigen::Matrix3Xd deadReckonSE2(const Eigen::Matrix3Xd& relative) {
  Eigen::Matrix3Xd absolute(3, relative.cols() + 1);
  Eigen::Matrix2d rotation = Eigen::Matrix2d::Identity();
  Eigen::Vector2d translation = Eigen::Vector2d::Zero();
  absolute.col(0).setZero();
  for (Eigen::Index k = 0; k < relative.cols(); ++k) {
    // T_{k+1} = T_k * v2t(dx, dy, dtheta)
    translation += rotation * relative.col(k).head<2>();
    rotation = rotation * Eigen::Rotation2Dd(relative(2, k)).toRotationMatrix();
    absolute.col(k + 1) << translation, std::atan2(rotation(1, 0), rotation(0, 0));
  }
  return absolute;
}

Eigen::Matrix3Xd readMatrix3xN(std::istream& in, const std::string& source_name) {
  std::vector<std::vector<double>> rows;
  std::size_t last_line = 0;
  forEachNumericLine(in, source_name, [&](const std::vector<double>& v, std::size_t line_no) {
    if (rows.size() == 3) fail(source_name, line_no, "more than 3 rows");
    if (!rows.empty() && v.size() != rows.front().size()) {
      fail(source_name, line_no,
           "expected " + std::to_string(rows.front().size()) + " columns like the first row, got " +
               std::to_string(v.size()));
    }
    rows.push_back(v);
    last_line = line_no;
  });
  if (rows.size() != 3) {
    fail(source_name, last_line, "expected 3 rows, got " + std::to_string(rows.size()));
  }
  Eigen::Matrix3Xd matrix(3, static_cast<Eigen::Index>(rows.front().size()));
  for (Eigen::Index r = 0; r < 3; ++r) {
    for (Eigen::Index c = 0; c < matrix.cols(); ++c) {
      matrix(r, c) = rows[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)];
    }
  }
  return matrix;
}

Eigen::Matrix3Xd readMatrix3xN(const std::string& path) {
  auto in = openForReading(path);
  return readMatrix3xN(in, path);
}

}  // namespace graphslam::io
