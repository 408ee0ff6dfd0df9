// SPDX-License-Identifier: MIT
// The format registry: one entry per format and kind of data, detection by extension and
// content, and the readers and writers of every registered format reached through it.
#include <gtest/gtest.h>

#include <sstream>

#include "../common/test_util.h"
#include "graphslam/io/graph_file.h"
#include "graphslam/io/register.h"
#include "graphslam/io/trajectory.h"
#include "graphslam/support/error.h"

using namespace graphslam;

namespace {

struct Note {
  std::string text;
};

io::Format<Note> noteFormat(const std::string& name, const std::string& ext, const char* magic) {
  io::Format<Note> f;
  f.name = name;
  f.extensions = {ext};
  f.sniff = [magic](std::string_view head) { return head.substr(0, 4) == magic; };
  f.read = [](io::Source& s, const io::ReadContext&) {
    return Note{std::string((std::istreambuf_iterator<char>(s.stream())), {})};
  };
  return f;
}

}  // namespace

TEST(Io_FormatRegistry, FormatsOfAKindAreFoundByNameExtensionAndContent) {
  io::FormatRegistry formats;
  formats.add(noteFormat("first", ".one", "AAAA"));
  formats.add(noteFormat("second", ".two", "BBBB"));
  EXPECT_EQ(formats.find<Note>("second")->name, "second");
  EXPECT_EQ(formats.find<Note>("third"), nullptr);
  EXPECT_EQ(formats.find<io::Trajectory>("first"), nullptr);  // another kind of data
  io::Source by_name = io::Source::fromText("BBBB", "x.one");
  EXPECT_EQ(formats.detect<Note>(by_name).name, "first");  // the only claim on .one
  io::Source by_content = io::Source::fromText("BBBB and more", "x.dat");
  EXPECT_EQ(formats.detect<Note>(by_content).name, "second");
  io::Source unknown = io::Source::fromText("CCCC", "x.dat");
  EXPECT_THROW_MSG((void)formats.detect<Note>(unknown), InputError, "cannot tell its format");
  EXPECT_EQ(formats.detect<Note>(unknown, "first").name, "first");
}

TEST(Io_FormatRegistry, NamesAreUniquePerKind) {
  io::FormatRegistry formats;
  formats.add(noteFormat("n", ".one", "AAAA"));
  EXPECT_THROW(formats.add(noteFormat("n", ".two", "BBBB")), RegistryError);
  io::Format<Note> useless;
  useless.name = "useless";
  EXPECT_THROW(formats.add(std::move(useless)), RegistryError);
}

TEST(Io_FormatRegistry, TheModuleRegistersEveryFormatItReads) {
  io::FormatRegistry formats;
  io::registerFormats(formats);
  for (const char* name : {"g2o", "toro", "isam", "npz", "matrix"}) {
    ASSERT_NE(formats.find<io::GraphFile>(name), nullptr) << name;
    EXPECT_TRUE(formats.find<io::GraphFile>(name)->read) << name;
  }
  for (const char* name : {"tum", "kitti"}) {
    ASSERT_NE(formats.find<io::Trajectory>(name), nullptr) << name;
    EXPECT_TRUE(formats.find<io::Trajectory>(name)->write) << name;
  }
  EXPECT_TRUE(formats.find<io::GraphFile>("g2o")->write);
}

TEST(Io_FormatRegistry, AmbiguousEdgesOnlyFileMustBeNamed) {
  io::FormatRegistry formats;
  io::registerFormats(formats);
  TypeRegistry types;
  io::ReadContext context;
  context.types = &types;
  io::Source s = io::Source::fromText("EDGE2 0 1 1 0 0 1 0 0 1 0 1\n", "edges.txt");
  const io::Format<io::GraphFile>& f = formats.detect<io::GraphFile>(s);
  EXPECT_THROW_MSG((void)f.read(s, context), InputError,
                   "edges.txt: EDGE2 lines without vertex lines are both TORO's and iSAM's");
}

TEST(Io_FormatRegistry, GraphsAreNotWrittenUnderATrajectoryName) {
  io::FormatRegistry formats;
  io::registerFormats(formats);
  TypeRegistry types;
  Graph g;
  EXPECT_THROW_MSG(io::writeGraph("/tmp/graphslam_never_written.tum", g, formats, {&types}),
                   InputError, "is named as a tum trajectory, not a graph");
}
