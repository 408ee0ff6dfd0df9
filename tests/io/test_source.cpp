// SPDX-License-Identifier: MIT
// Inputs are opened once: the head used to recognise a format is not lost, so pipes and
// FIFOs are read whole; outputs to devices and FIFOs are written in place, never renamed over.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <fstream>
#include <future>
#include <sstream>
#include <string>

#include "../common/test_util.h"
#include "graphslam/io/graph_file.h"
#include "graphslam/io/register.h"
#include "graphslam/io/source.h"
#include "graphslam/support/error.h"
#include "graphslam/support/file_util.h"
#include "graphslam/types_slam2d/register.h"

using namespace graphslam;
namespace fs = std::filesystem;

namespace {

/// A fresh folder of the test's own (never /dev).
fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("graphslam_source_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// A graph large enough that its text passes the 64 KiB head many times.
std::string chainText(int poses) {
  std::ostringstream text;
  for (int i = 0; i < poses; ++i) text << "VERTEX_SE2 " << i << " " << i << " 0 0\n";
  for (int i = 1; i < poses; ++i) {
    text << "EDGE_SE2 " << i - 1 << " " << i << " 1 0 0 1 0 0 1 0 1\n";
  }
  return text.str();
}

/// Writes `text` into the FIFO at `path` from another thread (the reader opens it).
std::future<void> feedFifo(const fs::path& path, std::string text) {
  return std::async(std::launch::async, [path, text = std::move(text)] {
    std::ofstream out(path, std::ios::binary);
    out << text;
  });
}

}  // namespace

TEST(Io_Source, HeadIsKeptForTheStream) {
  io::Source s = io::Source::fromText("EDGE_SE2 0 1\nrest", "t");
  EXPECT_EQ(s.head(4), "EDGE");
  std::string all((std::istreambuf_iterator<char>(s.stream())), std::istreambuf_iterator<char>());
  EXPECT_EQ(all, "EDGE_SE2 0 1\nrest");
}

TEST(Io_Source, FifoIsReadOnceAndWhole) {
  const fs::path dir = scratch("fifo");
  const fs::path fifo = dir / "graph.g2o";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0) << std::strerror(errno);
  const std::string text = chainText(6000);
  ASSERT_GT(text.size(), std::size_t{4} << 16);
  auto writer = feedFifo(fifo, text);
  io::FormatRegistry formats;
  io::registerFormats(formats);
  TypeRegistry types;
  types_slam2d::registerTypes(types);
  io::ReadContext context;
  context.types = &types;
  const io::GraphFile in = io::readGraph(fifo.string(), formats, context);
  writer.get();
  EXPECT_EQ(in.graph.numVertices(), 6000u);
  EXPECT_EQ(in.graph.numEdges(), 5999u);
  EXPECT_EQ(in.format, "g2o");
  fs::remove_all(dir);
}

TEST(Io_Source, FolderAndMissingFileAreNamed) {
  const fs::path dir = scratch("folder");
  EXPECT_THROW_MSG((void)io::Source::open(dir.string()), InputError, "is a folder, not a file");
  EXPECT_THROW_MSG((void)io::Source::open((dir / "none.g2o").string()), InputError,
                   "none.g2o: cannot open: No such file or directory");
  fs::remove_all(dir);
}

TEST(Io_Source, EmptyGraphIsAnError) {
  const fs::path dir = scratch("empty");
  std::ofstream(dir / "empty.g2o") << "# only a comment\n\n";
  io::FormatRegistry formats;
  io::registerFormats(formats);
  TypeRegistry types;
  io::ReadContext context;
  context.types = &types;
  EXPECT_THROW_MSG((void)io::readGraph((dir / "empty.g2o").string(), formats, context), InputError,
                   "empty.g2o: the graph is empty");
  fs::remove_all(dir);
}

TEST(Io_Output, FifoIsWrittenInPlace) {
  const fs::path dir = scratch("out_fifo");
  const fs::path fifo = dir / "out.g2o";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  auto reader = std::async(std::launch::async, [&] {
    std::ifstream in(fifo, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  });
  support::writeFileAtomically(fifo.string(), [](std::ostream& out) { out << "hello\n"; });
  EXPECT_EQ(reader.get(), "hello\n");
  struct stat st {};
  ASSERT_EQ(::stat(fifo.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode)) << "the FIFO was replaced";
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
  fs::remove_all(dir);
}

TEST(Io_Output, CharacterDeviceIsNotReplaced) {
  const fs::path dir = scratch("out_device");
  const fs::path node = dir / "null";
  if (::mknod(node.c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0) {
    GTEST_SKIP() << "cannot make a device node here: " << std::strerror(errno);
  }
  support::writeFileAtomically(node.string(), [](std::ostream& out) { out << "gone\n"; });
  struct stat st {};
  ASSERT_EQ(::stat(node.c_str(), &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode)) << "the device node was replaced by a regular file";
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
  fs::remove_all(dir);
}
