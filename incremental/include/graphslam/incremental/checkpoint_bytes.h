// SPDX-License-Identifier: MIT
// The byte records of checkpoint files (incremental's, and what callers such as DriveBot
// save in a checkpoint's note): numbers in the machine's byte order, strings and arrays of
// doubles with their lengths.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "graphslam/support/error.h"

namespace graphslam::incremental {

/// Appends numbers (in the machine's byte order), strings and arrays of doubles to a byte
/// string.
class ByteWriter {
 public:
  template <typename T>
  void put(T value) {
    out_.append(reinterpret_cast<const char*>(&value), sizeof value);
  }
  void putString(const std::string& s) {
    put<std::uint64_t>(s.size());
    out_ += s;
  }
  void putDoubles(const double* data, std::size_t n) {
    put<std::uint64_t>(n);
    out_.append(reinterpret_cast<const char*>(data), n * sizeof(double));
  }
  void putDoubles(const std::vector<double>& v) { putDoubles(v.data(), v.size()); }
  [[nodiscard]] const std::string& bytes() const { return out_; }

 private:
  std::string out_;
};

/// Reads what ByteWriter wrote from `bytes` (which must outlive the reader), refusing
/// (graphslam::InputError "FILE: checkpoint refused: ...") a record that would end past them.
class ByteReader {
 public:
  ByteReader(const std::string& bytes, std::string file) : in_(bytes), file_(std::move(file)) {}
  template <typename T>
  T get() {
    need(sizeof(T));
    T value;
    std::memcpy(&value, in_.data() + at_, sizeof value);
    at_ += sizeof value;
    return value;
  }
  std::string getString() {
    const auto n = get<std::uint64_t>();
    need(n);
    std::string s = in_.substr(at_, n);
    at_ += n;
    return s;
  }
  std::vector<double> getDoubles(std::size_t expected = SIZE_MAX) {
    const auto n = get<std::uint64_t>();
    if (expected != SIZE_MAX && n != expected)
      fail("a record holds " + std::to_string(n) + " values, its type " + std::to_string(expected));
    if (n > (in_.size() - at_) / sizeof(double))
      fail("its payload ends inside a record (inconsistent file)");
    std::vector<double> v(n);
    if (n) std::memcpy(v.data(), in_.data() + at_, n * sizeof(double));
    at_ += n * sizeof(double);
    return v;
  }
  [[nodiscard]] bool done() const { return at_ == in_.size(); }
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(file_ + ": checkpoint refused: " + what);
  }

 private:
  void need(std::uint64_t n) const {
    if (n > in_.size() - at_) fail("its payload ends inside a record (inconsistent file)");
  }
  const std::string& in_;
  std::size_t at_ = 0;
  std::string file_;
};

}  // namespace graphslam::incremental
