// SPDX-License-Identifier: MIT
// The NumPy .npy/.npz reader, on fixtures written by numpy (tests/data/npz/make_fixtures.py).
#include <gtest/gtest.h>

#include <string>

#include "graphslam/io/npz.h"
#include "graphslam/support/error.h"

using namespace graphslam;
using namespace graphslam::io;

namespace {

std::string fixture(const std::string& name) {
  return std::string(GRAPHSLAM_TEST_DATA_DIR) + "/npz/" + name;
}

/// The message of the InputError that `f` throws ("" if it throws none).
template <typename F>
std::string errorOf(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

const std::vector<double> kA = {0.5, 1.5, 2.5, 10.5, 11.5, 12.5};  // (2, 3), C order

TEST(Io_Npz, ListsArraysInArchiveOrder) {
  NpzArchive npz(fixture("arrays.npz"));
  ASSERT_GE(npz.names().size(), 10u);
  EXPECT_EQ(npz.names()[0], "c_f8");
  EXPECT_EQ(npz.names()[1], "fortran_f8");
  EXPECT_TRUE(npz.contains("text"));
  EXPECT_FALSE(npz.contains("c_f8.npy"));
}

TEST(Io_Npz, COrderAndFortranOrderGiveTheSameValues) {
  NpzArchive npz(fixture("arrays.npz"));
  const NpyArray c = npz.read("c_f8");
  const NpyArray f = npz.read("fortran_f8");
  EXPECT_EQ(c.descr, "<f8");
  EXPECT_FALSE(c.fortran_order);
  EXPECT_TRUE(f.fortran_order);
  EXPECT_EQ(c.shape, (std::vector<std::size_t>{2, 3}));
  EXPECT_EQ(f.shape, c.shape);
  EXPECT_EQ(c.data, kA);
  EXPECT_EQ(f.data, kA);
  EXPECT_EQ(f.at(1, 2), 12.5);
  EXPECT_EQ(f.matrix()(1, 0), 10.5);
  EXPECT_EQ(c.shapeString(), "(2, 3)");
}

TEST(Io_Npz, FortranOrderIn3d) {
  NpzArchive npz(fixture("arrays.npz"));
  const NpyArray f = npz.read("fortran_i8_3d");
  const NpyArray c = npz.read("c_i8_3d");
  EXPECT_TRUE(f.fortran_order);
  ASSERT_EQ(f.shape, (std::vector<std::size_t>{2, 3, 4}));
  EXPECT_EQ(f.data, c.data);
  for (std::size_t i = 0; i < 2; ++i)
    for (std::size_t j = 0; j < 3; ++j)
      for (std::size_t k = 0; k < 4; ++k)
        EXPECT_EQ(f.data[(i * 3 + j) * 4 + k], 100.0 * i + 10.0 * j + k) << i << j << k;
}

TEST(Io_Npz, ElementTypes) {
  NpzArchive npz(fixture("arrays.npz"));
  EXPECT_EQ(npz.read("big_f8").data, kA);
  const NpyArray f4 = npz.read("f4");
  EXPECT_EQ(f4.descr, "<f4");
  EXPECT_EQ(f4.data, kA);  // all exactly representable in float32
  EXPECT_EQ(npz.read("i4").data, (std::vector<double>{-3, 0, 7, 2147483647}));
  EXPECT_EQ(npz.read("i2").data, (std::vector<double>{-300, 5}));
  EXPECT_EQ(npz.read("i1").data, (std::vector<double>{-128, 127}));
  EXPECT_EQ(npz.read("u1").data, (std::vector<double>{0, 255}));
  EXPECT_EQ(npz.read("u2").data, (std::vector<double>{65535}));
  EXPECT_EQ(npz.read("u8").data, (std::vector<double>{9007199254740992.0}));
  EXPECT_EQ(npz.read("bool").data, (std::vector<double>{1, 0, 1}));
  const NpyArray scalar = npz.read("scalar");
  EXPECT_TRUE(scalar.shape.empty());
  EXPECT_EQ(scalar.data, (std::vector<double>{3.25}));
  EXPECT_EQ(scalar.shapeString(), "()");
  const NpyArray empty = npz.read("empty");
  EXPECT_EQ(empty.shape, (std::vector<std::size_t>{0, 2}));
  EXPECT_TRUE(empty.data.empty());
}

TEST(Io_Npz, CompressedArchiveAndPlainNpy) {
  NpzArchive npz(fixture("arrays_compressed.npz"));
  EXPECT_EQ(npz.read("c_f8").data, kA);
  EXPECT_EQ(npz.read("fortran_f8").data, kA);
  const NpyArray single = loadNpy(fixture("single.npy"));
  EXPECT_EQ(single.data, kA);
}

TEST(Io_Npz, FormatVersions2And3) {
  NpzArchive npz(fixture("members.npz"));
  EXPECT_EQ(npz.read("v2").data, kA);
  EXPECT_EQ(npz.read("v3").data, kA);
}

TEST(Io_Npz, UnsupportedAndCorruptMembersNameFileAndArray) {
  NpzArchive npz(fixture("members.npz"));
  const std::string prefix = fixture("members.npz") + ": array '";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"bad_magic", "bad magic string"},
      {"version9", "format version 9.0 is not supported"},
      {"short_data", "truncated data: shape (2, 3) of '<f8' needs 48 bytes, the array has 40"},
      {"long_data", "unexpected data"},
      {"short_header", "truncated .npy header"},
      {"bad_header", "malformed .npy header: expected '('"},
      {"unknown_key", "unexpected key 'fortran_ordr'"},
      {"structured", "structured (record) arrays are not supported"},
      {"complex", "element type '<c16' is not supported"},
      {"f2", "element type '<f2' is not supported"},
      {"object", "element type '|O' is not supported"},
      {"i8_too_big", "int64 value 9007199254740993 has no exact double"},
  };
  for (const auto& c : cases) {
    const std::string& name = c.first;  // not a structured binding: the lambda captures it
    const std::string& message = c.second;
    const std::string e = errorOf([&] { (void)npz.read(name); });
    EXPECT_EQ(e.rfind(prefix + name + "': ", 0), 0u) << name << ": " << e;
    EXPECT_NE(e.find(message), std::string::npos) << name << ": " << e;
  }
  NpzArchive arrays(fixture("arrays.npz"));
  EXPECT_NE(errorOf([&] { (void)arrays.read("text"); }).find("element type '<U3' is not supported"),
            std::string::npos);
  EXPECT_NE(errorOf([&] {
              (void)arrays.read("nothing");
            }).find("arrays.npz: array 'nothing': not in the archive (it has: c_f8, "),
            std::string::npos);
}

TEST(Io_Npz, CorruptArchives) {
  // A flipped byte under a stored member and inside deflated data: the CRC (or the
  // inflater) must catch it when the member is read.
  for (const char* file : {"bad_crc_stored.npz", "bad_crc_deflated.npz"}) {
    const std::string e = errorOf([&] {
      NpzArchive npz(fixture(file));
      (void)npz.read("c_f8");
    });
    EXPECT_NE(e.find(std::string(file) + ": array 'c_f8': corrupt member: "), std::string::npos)
        << e;
  }
  EXPECT_NE(errorOf([] {
              NpzArchive npz(fixture("bad_crc_stored.npz"));
              (void)npz.read("c_f8");
            }).find("CRC error"),
            std::string::npos);
  for (const char* file : {"truncated.npz", "not_a_zip.npz"}) {
    const std::string e = errorOf([&] { NpzArchive npz(fixture(file)); });
    EXPECT_NE(e.find(std::string(file) + ": not a readable .npz (zip) archive: "),
              std::string::npos)
        << e;
  }
  EXPECT_NE(errorOf([] { NpzArchive npz("/nonexistent/x.npz"); }).find("x.npz: cannot open"),
            std::string::npos);
  EXPECT_NE(errorOf([] { (void)loadNpy("/nonexistent/x.npy"); }).find("cannot open"),
            std::string::npos);
}

TEST(Io_Npz, ParseFromMemory) {
  // A hand-written version 1.0 file: 2 little-endian float64 in a (2,) array.
  std::string header = "{'descr': '<f8', 'fortran_order': False, 'shape': (2,), }";
  while ((10 + header.size() + 1) % 64) header += ' ';
  header += '\n';
  std::string bytes = std::string("\x93NUMPY\x01\x00", 8);
  bytes += static_cast<char>(header.size() & 0xff);
  bytes += static_cast<char>(header.size() >> 8);
  bytes += header;
  const double values[2] = {-1.25, 1e300};
  bytes.append(reinterpret_cast<const char*>(values), sizeof(values));
  const NpyArray a = parseNpy(bytes.data(), bytes.size(), "memory");
  EXPECT_EQ(a.data, (std::vector<double>{-1.25, 1e300}));
  EXPECT_EQ(a.shapeString(), "(2,)");
  EXPECT_EQ(a.matrix().rows(), 2);
  EXPECT_EQ(errorOf([&] { (void)parseNpy(bytes.data(), 5, "memory"); }).rfind("memory: ", 0), 0u);
}

}  // namespace
