// SPDX-License-Identifier: MIT
// Bounded reading and messages that say what is wrong: an endless line is refused after a
// bounded number of bytes by every text reader (.g2o with one and two threads, TUM, KITTI,
// the relative-pose matrix), and bytes a terminal would not show are escaped.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <sstream>
#include <streambuf>
#include <string>

#include "graphslam/io/g2o.h"
#include "graphslam/io/trajectory.h"
#include "graphslam/support/error.h"
#include "graphslam/types_slam2d/register.h"

using namespace graphslam;

namespace {

/// An input of `prefix` followed by an endless run of '1' (no line end); counts the bytes
/// handed out, so a test can tell how much a reader consumed before it stopped.
class EndlessLine : public std::streambuf {
 public:
  explicit EndlessLine(std::string prefix) : prefix_(std::move(prefix)) {}
  std::size_t served() const { return served_; }

 protected:
  int_type underflow() override {
    std::size_t n = 0;
    while (n < buffer_.size() && next_ < prefix_.size()) buffer_[n++] = prefix_[next_++];
    while (n < buffer_.size()) buffer_[n++] = '1';
    served_ += n;
    setg(buffer_.data(), buffer_.data(), buffer_.data() + n);
    return traits_type::to_int_type(buffer_[0]);
  }
  std::streamsize xsgetn(char* s, std::streamsize count) override {
    std::streamsize done = 0;
    while (done < count) {
      if (gptr() == egptr() && underflow() == traits_type::eof()) break;
      const std::streamsize n = std::min<std::streamsize>(count - done, egptr() - gptr());
      std::copy(gptr(), gptr() + n, s + done);
      gbump(static_cast<int>(n));
      done += n;
    }
    return done;
  }

 private:
  std::string prefix_;
  std::size_t next_ = 0;
  std::size_t served_ = 0;
  std::array<char, 4096> buffer_{};
};

}  // namespace

TEST(Io_BoundedInput, G2oEndlessLineIsRefusedAfterBoundedReading) {
  TypeRegistry types;
  types_slam2d::registerTypes(types);
  for (int threads : {1, 2}) {
    for (bool strict : {true, false}) {
      EndlessLine buf("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 ");
      std::istream in(&buf);
      io::LoadOptions options;
      options.threads = threads;
      options.strict = strict;
      options.chunk_bytes = 1000;
      options.max_line_bytes = 10000;
      const auto r = io::readG2o(in, "long.g2o", types, options);
      ASSERT_FALSE(r.ok()) << "threads " << threads << " strict " << strict;
      ASSERT_FALSE(r.diagnostics.empty());
      EXPECT_EQ(r.diagnostics.back().str(),
                "long.g2o:2: the line is longer than 10000 bytes: "
                "not a .g2o line");
      EXPECT_LT(buf.served(), 10000u + 3 * 4096u) << "threads " << threads;
      EXPECT_EQ(r.graph.numVertices(), 1u);
    }
  }
}

TEST(Io_BoundedInput, G2oLongLineInsideAChunkIsRefused) {
  TypeRegistry types;
  types_slam2d::registerTypes(types);
  const std::string text = "VERTEX_SE2 0 0 0 0\n# " + std::string(300, 'x') + "\n";
  io::LoadOptions options;
  options.max_line_bytes = 100;  // the chunk (4 MiB) holds the whole text
  std::istringstream in(text);
  const auto r = io::readG2o(in, "c.g2o", types, options);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.diagnostics.back().str().find("c.g2o:2: the line is longer than 100 bytes"),
            std::string::npos);
  options.max_line_bytes = 1000;
  std::istringstream again(text);
  EXPECT_TRUE(io::readG2o(again, "c.g2o", types, options).ok());
}

TEST(Io_BoundedInput, TrajectoryReadersRefuseAnEndlessLine) {
  using ReadFn = io::Trajectory (*)(std::istream&, const std::string&);
  for (ReadFn read : {static_cast<ReadFn>(&io::readTum), static_cast<ReadFn>(&io::readKitti)}) {
    EndlessLine buf("");
    std::istream in(&buf);
    try {
      (void)read(in, "long.txt");
      FAIL() << "an endless line was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("long.txt:1: the line is longer than 1048576 bytes"),
                std::string::npos)
          << e.what();
    }
    EXPECT_LT(buf.served(), (std::size_t{1} << 20) + 2 * 4096u);
  }
  EndlessLine buf("1 2 3\n");
  std::istream in(&buf);
  EXPECT_THROW((void)io::readMatrix3xN(in, "m.txt"), InputError);
}

TEST(Io_BoundedInput, TextReadersEscapeInvisibleBytes) {
  std::istringstream in(
      "\xEF\xBB\xBF"
      "1 0 0 0 0 0 0 1\n");
  try {
    (void)io::readTum(in, "bom.tum");
    FAIL() << "a byte-order mark was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "bom.tum:1: token 1 '\\xEF\\xBB\\xBF1' (a UTF-8 byte-order mark: save the file "
              "without one) is not a number");
  }
  std::istringstream big("1e400 0 0 0 0 0 0 1\n");
  EXPECT_THROW(
      {
        try {
          (void)io::readTum(big, "big.tum");
        } catch (const InputError& e) {
          EXPECT_EQ(std::string(e.what()),
                    "big.tum:1: token 1 '1e400' is out of the range of a double");
          throw;
        }
      },
      InputError);
}
