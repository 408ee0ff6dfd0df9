// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <istream>
#include <memory>
#include <string>
#include <string_view>

namespace graphslam::io {

/// An input opened exactly once: a regular file, standard input ("-" or /dev/stdin), a pipe,
/// a FIFO or a character device. Its first bytes can be looked at (head(), to recognise the
/// format) without losing them: stream() then yields the input from its very first byte, so
/// a pipe or FIFO is read once and whole, never reopened.
class Source {
 public:
  /// Opens `path` ("-": standard input). Throws graphslam::InputError "PATH: cannot open:
  /// REASON" (the system's), or "PATH: is a folder, not a file".
  [[nodiscard]] static Source open(const std::string& path);
  /// A source over text held in memory (tests, translated formats); `name` is for messages.
  [[nodiscard]] static Source fromText(std::string text, std::string name);

  Source(Source&&) noexcept;
  Source& operator=(Source&&) noexcept;
  ~Source();

  /// The path as given (for messages).
  [[nodiscard]] const std::string& name() const { return name_; }
  /// True for a regular file: readers that need a path of their own may reopen it.
  [[nodiscard]] bool isRegularFile() const { return regular_; }
  /// Up to `bytes` first bytes of the input (fewer at its end). Kept: the stream still
  /// starts at the first byte.
  [[nodiscard]] std::string_view head(std::size_t bytes = std::size_t{64} << 10);
  /// The input from its first byte. Reading it consumes the source (one pass).
  [[nodiscard]] std::istream& stream();
  /// The whole input in memory; throws graphslam::InputError when it holds more than
  /// `max_bytes` ("PATH: larger than N bytes").
  [[nodiscard]] std::string readAll(std::size_t max_bytes);

 private:
  struct Impl;
  Source(std::string name, bool regular, std::unique_ptr<Impl> impl);
  std::string name_;
  bool regular_ = false;
  std::unique_ptr<Impl> impl_;
};

}  // namespace graphslam::io
