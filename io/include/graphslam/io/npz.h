// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace graphslam::io {

/// One numeric array read from a NumPy `.npy` file (format versions 1.0, 2.0 and 3.0).
/// Element types: little- or big-endian float64, float32, signed and unsigned integers of
/// 1, 2, 4 and 8 bytes, and bool; every value is converted to double (an 8-byte integer
/// that a double cannot hold exactly is an error). Values are stored in C (row-major)
/// order whatever the file's order was.
struct NpyArray {
  std::string descr;               ///< element type as written in the file, e.g. "<f8"
  std::vector<std::size_t> shape;  ///< empty for a 0-d (scalar) array
  bool fortran_order = false;      ///< how the file stored it (data below is C order)
  std::vector<double> data;        ///< product(shape) values, C order

  [[nodiscard]] std::size_t size() const { return data.size(); }
  /// Element (i, j) of a 2-d array, unchecked.
  [[nodiscard]] double at(std::size_t i, std::size_t j) const { return data[i * shape[1] + j]; }
  /// The shape as text, NumPy style: "(766, 4)", "(3,)", "()".
  [[nodiscard]] std::string shapeString() const;
  /// A 2-d array as a matrix (a 1-d array as a column). Throws InputError otherwise.
  [[nodiscard]] Eigen::MatrixXd matrix() const;
};

/// Parses the bytes of one `.npy` file. `what` names the array in error messages (e.g.
/// "data.npz: array 'odom'"). Throws graphslam::InputError, prefixed with `what`, for a
/// bad magic string, an unknown version, a malformed header, an unsupported element type
/// (strings, objects, structured, complex, float16) or a payload whose length does not
/// match the shape.
[[nodiscard]] NpyArray parseNpy(const void* bytes, std::size_t size, const std::string& what);

/// Reads a `.npy` file. Throws InputError naming the file.
[[nodiscard]] NpyArray loadNpy(const std::string& path);

/// A NumPy `.npz` archive (a zip of `.npy` files, as written by numpy.savez and
/// savez_compressed; stored and deflated members) read with libzip. Members are read
/// whole, so their CRC-32 is verified. Every error is a graphslam::InputError naming the
/// file and, for a member, the array.
class NpzArchive {
 public:
  /// Opens the archive and lists its members. Throws InputError when the file is missing
  /// or is not a readable zip archive.
  explicit NpzArchive(const std::string& path);
  /// The archive held in `bytes` (read from a pipe or standard input); `name` names it in
  /// messages.
  [[nodiscard]] static NpzArchive fromBytes(std::string bytes, const std::string& name);
  ~NpzArchive();
  NpzArchive(NpzArchive&&) noexcept;
  NpzArchive& operator=(NpzArchive&&) noexcept;
  NpzArchive(const NpzArchive&) = delete;
  NpzArchive& operator=(const NpzArchive&) = delete;

  [[nodiscard]] const std::string& path() const;
  /// Array names (member names without ".npy"), in archive order.
  [[nodiscard]] const std::vector<std::string>& names() const;
  [[nodiscard]] bool contains(const std::string& name) const;
  /// Reads and parses one array. Throws InputError ("FILE: array 'NAME': ...") when it is
  /// missing, corrupt (bad CRC, truncated, bad compressed data) or unsupported.
  [[nodiscard]] NpyArray read(const std::string& name) const;

 private:
  NpzArchive();
  void listMembers();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace graphslam::io
