// SPDX-License-Identifier: MIT
// Bounded reading and messages that say what is wrong: an endless line is refused after a
// bounded number of bytes by every text reader (.g2o with one and two threads, TUM, KITTI,
// the relative-pose matrix); an initial chi2 that is not finite names its edge and tells an
// overflow from a non-finite error; an edge whose information matrix spans more than double
// arithmetic resolves is named as the reason a vertex is undetermined.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <sstream>
#include <streambuf>
#include <string>

#include "graphslam/core/error.h"
#include "graphslam/core/io_g2o.h"
#include "graphslam/core/observability.h"
#include "graphslam/core/optimizer.h"
#include "graphslam/eval/trajectory.h"
#include "graphslam/solvers/register.h"
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

TEST(Core_BoundedInput, G2oEndlessLineIsRefusedAfterBoundedReading) {
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

TEST(Core_BoundedInput, G2oLongLineInsideAChunkIsRefused) {
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

TEST(Core_BoundedInput, TrajectoryReadersRefuseAnEndlessLine) {
  using ReadFn = eval::Trajectory (*)(std::istream&, const std::string&);
  for (ReadFn read : {static_cast<ReadFn>(&eval::readTum), static_cast<ReadFn>(&eval::readKitti)}) {
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
  EXPECT_THROW((void)eval::readMatrix3xN(in, "m.txt"), InputError);
}

TEST(Core_BoundedInput, TextReadersEscapeInvisibleBytes) {
  std::istringstream in(
      "\xEF\xBB\xBF"
      "1 0 0 0 0 0 0 1\n");
  try {
    (void)eval::readTum(in, "bom.tum");
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
          (void)eval::readTum(big, "big.tum");
        } catch (const InputError& e) {
          EXPECT_EQ(std::string(e.what()),
                    "big.tum:1: token 1 '1e400' is out of the range of a double");
          throw;
        }
      },
      InputError);
}

namespace {

/// Two poses, the first fixed, joined by one EDGE_SE2 with `measurement_x` and the
/// information diag(i, i, 1) written as text.
io::LoadResult twoPoses(const TypeRegistry& types, const std::string& measurement_x,
                        const std::string& info) {
  std::istringstream in("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 0 0 0\nFIX 0\nEDGE_SE2 0 1 " +
                        measurement_x + " 0 0 " + info + " 0 0 " + info + " 0 1\n");
  return io::readG2o(in, "t.g2o", types);
}

}  // namespace

TEST(Core_BoundedInput, NonFiniteInitialChi2NamesTheEdgeAndTheOverflow) {
  TypeRegistry types;
  types_slam2d::registerTypes(types);
  SolverRegistry solvers;
  solvers::registerSolvers(solvers);
  // Optimises the two poses from their file estimates (no initialisation).
  const auto optimize = [&](const std::string& measurement_x, const std::string& info) {
    auto r = twoPoses(types, measurement_x, info);
    EXPECT_TRUE(r.ok());
    Optimizer opt(r.graph, solvers);
    return opt.optimize();
  };
  const Summary huge_error = optimize("1e300", "1e300");  // error 1e300: chi2 overflows
  EXPECT_EQ(huge_error.status, TerminationStatus::kNumericalFailure);
  EXPECT_EQ(huge_error.failed_edge, 0);
  EXPECT_NE(huge_error.message.find("initial chi2 is not finite: the edge joining vertices 0, 1: "
                                    "its error is finite (largest entry 1e+300) but e^T Omega e "
                                    "overflows"),
            std::string::npos)
      << huge_error.message;
  const Summary huge_information = optimize("10", "1e308");
  EXPECT_EQ(huge_information.failed_edge, 0);
  EXPECT_NE(huge_information.message.find(
                "overflows the range of a double (information entries up to 1e+308)"),
            std::string::npos)
      << huge_information.message;
  const Summary fine = optimize("10", "1");
  EXPECT_TRUE(fine.succeeded()) << fine.message;
  EXPECT_EQ(fine.failed_edge, -1);
}

TEST(Core_BoundedInput, IllConditionedInformationIsNamedAsTheReason) {
  TypeRegistry types;
  types_slam2d::registerTypes(types);
  auto r = twoPoses(types, "1", "1e308");  // diag(1e308, 1e308, 1): positive definite
  ASSERT_TRUE(r.ok());
  const ObservabilityReport report = checkObservability(r.graph);
  ASSERT_EQ(report.undetermined.size(), 1u);
  EXPECT_NE(report.undetermined[0].reason.find(
                "the information matrix of one of its edges has eigenvalues 1e+308 times apart"),
            std::string::npos)
      << report.undetermined[0].reason;
  auto fine = twoPoses(types, "1", "1e6");
  ASSERT_TRUE(fine.ok());
  EXPECT_TRUE(checkObservability(fine.graph).ok());
}
