// SPDX-License-Identifier: MIT
#include "graphslam/core/internal/file_util.h"

#include <unistd.h>

#include <array>
#include <charconv>
#include <cstdio>
#include <fstream>

#include "graphslam/core/error.h"

namespace graphslam {

void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  try {
    {
      std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
      if (!out)
        throw Error("cannot write '" + path + "': cannot create temporary file '" + tmp + "'");
      write(out);
      out.flush();
      if (!out) throw Error("cannot write '" + path + "': write error");
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
      throw Error("cannot write '" + path + "': rename of the temporary file failed");
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

}  // namespace graphslam
