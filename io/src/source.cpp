// SPDX-License-Identifier: MIT
#include "graphslam/io/source.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <streambuf>
#include <vector>

#include "graphslam/support/error.h"
#include "graphslam/support/file_util.h"

namespace graphslam::io {

namespace {

/// A stream buffer over a file descriptor that first serves the bytes already read ahead
/// (the head), then reads on. Holds no more than one block besides the head.
class DescriptorBuffer final : public std::streambuf {
 public:
  DescriptorBuffer(int fd, std::string name) : fd_(fd), name_(std::move(name)) {}
  ~DescriptorBuffer() override {
    if (fd_ >= 0 && fd_ != STDIN_FILENO) ::close(fd_);
  }
  DescriptorBuffer(const DescriptorBuffer&) = delete;
  DescriptorBuffer& operator=(const DescriptorBuffer&) = delete;

  /// Reads ahead until `bytes` are buffered or the input ends; the get area keeps them.
  std::string_view peek(std::size_t bytes) {
    while (buffer_.size() < bytes && !eof_) {
      const std::size_t old = buffer_.size();
      buffer_.resize(bytes);
      const ssize_t got = readSome(buffer_.data() + old, bytes - old);
      buffer_.resize(old + static_cast<std::size_t>(got > 0 ? got : 0));
      if (got <= 0) eof_ = true;
    }
    setg(buffer_.data(), buffer_.data(), buffer_.data() + buffer_.size());
    return std::string_view(buffer_.data(), std::min(bytes, buffer_.size()));
  }

 protected:
  int_type underflow() override {
    if (gptr() < egptr()) return traits_type::to_int_type(*gptr());
    if (eof_) return traits_type::eof();
    buffer_.resize(kBlock);
    const ssize_t got = readSome(buffer_.data(), kBlock);
    if (got <= 0) {
      eof_ = true;
      buffer_.clear();
      setg(nullptr, nullptr, nullptr);
      return traits_type::eof();
    }
    setg(buffer_.data(), buffer_.data(), buffer_.data() + got);
    return traits_type::to_int_type(*gptr());
  }

 private:
  static constexpr std::size_t kBlock = std::size_t{1} << 16;

  ssize_t readSome(char* out, std::size_t bytes) {
    for (;;) {
      const ssize_t got = ::read(fd_, out, bytes);
      if (got >= 0) return got;
      if (errno == EINTR) continue;
      throw InputError(name_ + ": cannot read: " + std::strerror(errno));
    }
  }

  int fd_;
  std::string name_;
  std::vector<char> buffer_;
  bool eof_ = false;
};

/// The same interface over text held in memory.
class TextBuffer final : public std::streambuf {
 public:
  explicit TextBuffer(std::string text) : text_(std::move(text)) {
    setg(text_.data(), text_.data(), text_.data() + text_.size());
  }
  std::string_view peek(std::size_t bytes) const {
    return std::string_view(text_).substr(0, bytes);
  }

 private:
  std::string text_;
};

}  // namespace

struct Source::Impl {
  std::unique_ptr<DescriptorBuffer> file;
  std::unique_ptr<TextBuffer> text;
  std::istream stream{nullptr};
  bool consumed = false;
};

Source::Source(std::string name, bool regular, std::unique_ptr<Impl> impl)
    : name_(std::move(name)), regular_(regular), impl_(std::move(impl)) {}
Source::Source(Source&&) noexcept = default;
Source& Source::operator=(Source&&) noexcept = default;
Source::~Source() = default;

Source Source::open(const std::string& path) {
  const bool is_stdin = path == "-";
  const int fd = is_stdin ? STDIN_FILENO : ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw InputError(support::cannotOpenMessage(path, errno));
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    const int error = errno;
    if (!is_stdin) ::close(fd);
    throw InputError(support::cannotOpenMessage(path, error));
  }
  if (S_ISDIR(st.st_mode)) {
    if (!is_stdin) ::close(fd);
    throw InputError(path + ": is a folder, not a file");
  }
  auto impl = std::make_unique<Impl>();
  impl->file = std::make_unique<DescriptorBuffer>(fd, path);
  impl->stream.rdbuf(impl->file.get());
  return Source(is_stdin ? "standard input" : path, S_ISREG(st.st_mode) && !is_stdin,
                std::move(impl));
}

Source Source::fromText(std::string text, std::string name) {
  auto impl = std::make_unique<Impl>();
  impl->text = std::make_unique<TextBuffer>(std::move(text));
  impl->stream.rdbuf(impl->text.get());
  return Source(std::move(name), false, std::move(impl));
}

std::string_view Source::head(std::size_t bytes) {
  if (impl_->consumed) throw Error(name_ + ": head() after the input was read");
  return impl_->file ? impl_->file->peek(bytes) : impl_->text->peek(bytes);
}

std::istream& Source::stream() {
  if (impl_->consumed) throw Error(name_ + ": the input was read already");
  impl_->consumed = true;
  return impl_->stream;
}

std::string Source::readAll(std::size_t max_bytes) {
  std::istream& in = stream();
  std::string out;
  char block[1 << 16];
  while (in.read(block, sizeof block) || in.gcount() > 0) {
    out.append(block, static_cast<std::size_t>(in.gcount()));
    if (out.size() > max_bytes) {
      throw InputError(name_ + ": larger than " + std::to_string(max_bytes) + " bytes");
    }
  }
  return out;
}

}  // namespace graphslam::io
