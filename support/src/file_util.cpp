// SPDX-License-Identifier: MIT
#include "graphslam/support/file_util.h"

#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <istream>

#include "graphslam/support/error.h"
#include "graphslam/support/signal_cleanup.h"

namespace graphslam::support {

namespace {
/// Writes straight into a character device, a FIFO or standard output ("-"): there is no
/// file to replace, and renaming over a device node would turn it into a regular file.
void writeInPlace(const std::string& path, const std::function<void(std::ostream&)>& write) {
  errno = 0;
  std::ofstream out;
  if (path == "-") {
    out.open("/dev/stdout", std::ios::binary | std::ios::app);
  } else {
    out.open(path, std::ios::binary | std::ios::app);
  }
  if (!out) throw Error("cannot write '" + path + "': " + std::strerror(errno ? errno : EIO));
  write(out);
  out.flush();
  if (!out) throw Error("cannot write '" + path + "': " + std::strerror(errno ? errno : EIO));
}
}  // namespace

bool isStreamOutput(const std::string& path) {
  if (path == "-") return true;
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && (S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode));
}

void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  if (isStreamOutput(path)) {
    writeInPlace(path, write);
    return;
  }
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  const TemporaryFile on_signal(tmp);
  // The system's reason (errno) of the failed call, e.g. "File too large" under a file size
  // limit, "No space left on device" on a full disk.
  const auto reason = [] {
    return std::string(errno != 0 ? std::strerror(errno) : "unknown reason");
  };
  try {
    {
      errno = 0;
      std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
      if (!out) {
        throw Error("cannot write '" + path + "': " + reason());
      }
      write(out);
      out.flush();
      if (!out) throw Error("cannot write '" + path + "': " + reason());
      out.close();
      if (out.fail()) throw Error("cannot write '" + path + "': " + reason());
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
      throw Error("cannot write '" + path + "': rename of the temporary file failed: " + reason());
    }
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
}

std::string formatDouble(double value) {
  std::array<char, 32> buf{};
  auto res = std::to_chars(buf.data(), buf.data() + buf.size(), value);
  return std::string(buf.data(), res.ptr);
}

void appendDouble(std::string& out, double value, char separator) {
  std::array<char, 32> buf{};
  buf[0] = separator;
  auto res = std::to_chars(buf.data() + 1, buf.data() + buf.size(), value);
  out.append(buf.data(), res.ptr);
}

LineRead readBoundedLine(std::istream& in, std::string& line, std::size_t max_bytes) {
  line.clear();
  std::streambuf* buf = in.rdbuf();
  if (!in.good() || !buf) return LineRead::kEnd;
  bool any = false;
  while (true) {
    const int c = buf->sbumpc();
    if (c == std::char_traits<char>::eof()) {
      in.setstate(std::ios::eofbit);
      return any ? LineRead::kLine : LineRead::kEnd;
    }
    any = true;
    if (c == '\n') return LineRead::kLine;
    if (line.size() >= max_bytes) return LineRead::kTooLong;
    line.push_back(static_cast<char>(c));
  }
}

std::string cannotOpenMessage(const std::string& path, int error_number) {
  return path +
         ": cannot open: " + (error_number != 0 ? std::strerror(error_number) : "unknown reason");
}

}  // namespace graphslam::support
