// SPDX-License-Identifier: MIT
#include "graphslam/io/npz.h"

#include "zip_api.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <optional>
#include <sstream>

#include "graphslam/support/error.h"
#include "graphslam/support/file_util.h"

namespace graphslam::io {

using detail::zipApi;

namespace {

constexpr char kMagic[] = "\x93NUMPY";
constexpr std::size_t kMagicSize = 6;

[[noreturn]] void fail(const std::string& what, const std::string& message) {
  throw InputError(what + ": " + message);
}

bool hostIsLittleEndian() {
  const std::uint16_t one = 1;
  unsigned char first = 0;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

/// The header dictionary: {'descr': '<f8', 'fortran_order': False, 'shape': (3, 4), }.
struct Header {
  std::string descr;
  bool fortran_order = false;
  std::vector<std::size_t> shape;
};

/// Recursive-descent reader of the Python literal subset NumPy writes in .npy headers.
class HeaderParser {
 public:
  HeaderParser(std::string text, std::string what) : s_(std::move(text)), what_(std::move(what)) {}

  Header parse() {
    Header h;
    bool have_descr = false, have_order = false, have_shape = false;
    expect('{');
    while (true) {
      skipSpace();
      if (peek() == '}') break;
      const std::string key = parseString();
      expect(':');
      skipSpace();
      if (key == "descr") {
        if (peek() == '[') {
          fail(what_, "structured (record) arrays are not supported, only plain numeric arrays");
        }
        h.descr = parseString();
        have_descr = true;
      } else if (key == "fortran_order") {
        h.fortran_order = parseBool();
        have_order = true;
      } else if (key == "shape") {
        h.shape = parseShape();
        have_shape = true;
      } else {
        fail(what_, "unexpected key '" + key + "' in the .npy header");
      }
      skipSpace();
      if (peek() == ',') {
        ++pos_;
        continue;
      }
      if (peek() != '}') error("',' or '}'");
    }
    ++pos_;
    if (!have_descr || !have_order || !have_shape) {
      fail(what_, std::string("the .npy header lacks '") +
                      (!have_descr   ? "descr"
                       : !have_order ? "fortran_order"
                                     : "shape") +
                      "'");
    }
    return h;
  }

 private:
  [[nodiscard]] char peek() const { return pos_ < s_.size() ? s_[pos_] : '\0'; }
  void skipSpace() {
    while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
  }
  [[noreturn]] void error(const std::string& expected) const {
    fail(what_, "malformed .npy header: expected " + expected + " at column " +
                    std::to_string(pos_ + 1) + " of \"" + s_.substr(0, 120) + "\"");
  }
  void expect(char c) {
    skipSpace();
    if (peek() != c) error(std::string("'") + c + "'");
    ++pos_;
  }
  std::string parseString() {
    skipSpace();
    const char quote = peek();
    if (quote != '\'' && quote != '"') error("a quoted string");
    const std::size_t end = s_.find(quote, pos_ + 1);
    if (end == std::string::npos) error("a closing quote");
    std::string out = s_.substr(pos_ + 1, end - pos_ - 1);
    pos_ = end + 1;
    return out;
  }
  bool parseBool() {
    if (s_.compare(pos_, 4, "True") == 0) {
      pos_ += 4;
      return true;
    }
    if (s_.compare(pos_, 5, "False") == 0) {
      pos_ += 5;
      return false;
    }
    error("True or False");
  }
  std::vector<std::size_t> parseShape() {
    std::vector<std::size_t> shape;
    expect('(');
    while (true) {
      skipSpace();
      if (peek() == ')') break;
      if (!std::isdigit(static_cast<unsigned char>(peek()))) error("a non-negative integer");
      std::size_t value = 0;
      while (std::isdigit(static_cast<unsigned char>(peek()))) {
        const std::size_t digit = static_cast<std::size_t>(peek() - '0');
        if (value > (std::numeric_limits<std::size_t>::max() - digit) / 10) error("a smaller size");
        value = value * 10 + digit;
        ++pos_;
      }
      if (peek() == 'L') ++pos_;  // Python 2 long literal
      shape.push_back(value);
      skipSpace();
      if (peek() == ',') {
        ++pos_;
      } else if (peek() != ')') {
        error("',' or ')'");
      }
    }
    ++pos_;
    return shape;
  }

  std::string s_;
  std::string what_;
  std::size_t pos_ = 0;
};

/// Element type of a descr such as "<f8", ">i4", "|u1", "|b1".
struct ElementType {
  char kind = 'f';  ///< 'f' float, 'i' signed, 'u' unsigned, 'b' bool
  std::size_t size = 8;
  bool swap = false;  ///< byte order differs from the host's
};

ElementType parseDescr(const std::string& descr, const std::string& what) {
  const std::string unsupported = "element type '" + descr +
                                  "' is not supported (numbers only: float64, float32, "
                                  "signed/unsigned integers, bool)";
  std::size_t i = 0;
  char order = '=';
  if (!descr.empty() && std::strchr("<>|=", descr[0]) != nullptr) order = descr[i++];
  if (i >= descr.size()) fail(what, unsupported);
  ElementType t;
  t.kind = descr[i++];
  const std::string digits = descr.substr(i);
  if (digits.empty() || digits.size() > 2 || !std::all_of(digits.begin(), digits.end(), [](char c) {
        return std::isdigit(static_cast<unsigned char>(c)) != 0;
      })) {
    fail(what, unsupported);
  }
  t.size = static_cast<std::size_t>(std::stoi(digits));
  const bool ok = (t.kind == 'f' && (t.size == 4 || t.size == 8)) ||
                  ((t.kind == 'i' || t.kind == 'u') &&
                   (t.size == 1 || t.size == 2 || t.size == 4 || t.size == 8)) ||
                  (t.kind == 'b' && t.size == 1);
  if (!ok) fail(what, unsupported);
  const bool little = hostIsLittleEndian();
  t.swap = t.size > 1 && ((order == '<' && !little) || (order == '>' && little));
  return t;
}

template <typename T>
T readValue(const unsigned char* p, bool swap) {
  unsigned char buf[sizeof(T)];
  std::memcpy(buf, p, sizeof(T));
  if (swap) std::reverse(buf, buf + sizeof(T));
  T value;
  std::memcpy(&value, buf, sizeof(T));
  return value;
}

/// Converts one element; throws when an 8-byte integer has no exact double.
double toDouble(const unsigned char* p, const ElementType& t, const std::string& what) {
  switch (t.kind) {
    case 'f':
      return t.size == 8 ? readValue<double>(p, t.swap)
                         : static_cast<double>(readValue<float>(p, t.swap));
    case 'b':
      return *p != 0 ? 1.0 : 0.0;
    case 'i':
      switch (t.size) {
        case 1:
          return readValue<std::int8_t>(p, false);
        case 2:
          return readValue<std::int16_t>(p, t.swap);
        case 4:
          return readValue<std::int32_t>(p, t.swap);
        default: {
          const std::int64_t v = readValue<std::int64_t>(p, t.swap);
          const double d = static_cast<double>(v);
          if (d >= 9223372036854775808.0 || static_cast<std::int64_t>(d) != v) {
            fail(what, "int64 value " + std::to_string(v) + " has no exact double");
          }
          return d;
        }
      }
    default:  // 'u'
      switch (t.size) {
        case 1:
          return readValue<std::uint8_t>(p, false);
        case 2:
          return readValue<std::uint16_t>(p, t.swap);
        case 4:
          return readValue<std::uint32_t>(p, t.swap);
        default: {
          const std::uint64_t v = readValue<std::uint64_t>(p, t.swap);
          const double d = static_cast<double>(v);
          if (d >= 18446744073709551616.0 || static_cast<std::uint64_t>(d) != v) {
            fail(what, "uint64 value " + std::to_string(v) + " has no exact double");
          }
          return d;
        }
      }
  }
}

}  // namespace

std::string NpyArray::shapeString() const {
  std::string s = "(";
  for (std::size_t i = 0; i < shape.size(); ++i) {
    if (i) s += ", ";
    s += std::to_string(shape[i]);
  }
  if (shape.size() == 1) s += ",";
  return s + ")";
}

Eigen::MatrixXd NpyArray::matrix() const {
  if (shape.size() == 1) return Eigen::Map<const Eigen::VectorXd>(data.data(), shape[0]);
  if (shape.size() != 2) {
    throw InputError("array of shape " + shapeString() + " is not a matrix");
  }
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      data.data(), static_cast<Eigen::Index>(shape[0]), static_cast<Eigen::Index>(shape[1]));
}

NpyArray parseNpy(const void* bytes, std::size_t size, const std::string& what) {
  const auto* p = static_cast<const unsigned char*>(bytes);
  if (size < kMagicSize + 2 || std::memcmp(p, kMagic, kMagicSize) != 0) {
    fail(what, "not a .npy array (bad magic string; expected \\x93NUMPY)");
  }
  const int major = p[6];
  const int minor = p[7];
  if (major < 1 || major > 3) {
    fail(what, ".npy format version " + std::to_string(major) + "." + std::to_string(minor) +
                   " is not supported (1.0, 2.0, 3.0 are)");
  }
  const std::size_t len_size = major == 1 ? 2 : 4;
  const std::size_t prefix = kMagicSize + 2 + len_size;
  if (size < prefix) fail(what, "truncated .npy header");
  std::size_t header_len = 0;
  for (std::size_t i = 0; i < len_size; ++i) header_len |= std::size_t{p[8 + i]} << (8 * i);
  if (size - prefix < header_len) {
    fail(what, "truncated .npy header (" + std::to_string(header_len) + " bytes announced, " +
                   std::to_string(size - prefix) + " present)");
  }
  const std::string text(reinterpret_cast<const char*>(p + prefix), header_len);
  const Header h = HeaderParser(text, what).parse();
  const ElementType type = parseDescr(h.descr, what);

  NpyArray a;
  a.descr = h.descr;
  a.shape = h.shape;
  a.fortran_order = h.fortran_order;
  std::size_t count = 1;
  for (std::size_t d : h.shape) {
    if (d != 0 && count > std::numeric_limits<std::size_t>::max() / type.size / d) {
      fail(what, "shape " + a.shapeString() + " is too large");
    }
    count *= d;
  }
  const std::size_t payload = size - prefix - header_len;
  if (payload != count * type.size) {
    fail(what, std::string(payload < count * type.size ? "truncated data" : "unexpected data") +
                   ": shape " + a.shapeString() + " of '" + h.descr + "' needs " +
                   std::to_string(count * type.size) + " bytes, the array has " +
                   std::to_string(payload));
  }
  const unsigned char* data = p + prefix + header_len;
  a.data.resize(count);
  if (!h.fortran_order || h.shape.size() < 2) {
    for (std::size_t k = 0; k < count; ++k) a.data[k] = toDouble(data + k * type.size, type, what);
    return a;
  }
  // Fortran order: the first index varies fastest in the file. Walk the file in order with
  // an odometer over the multi-index and write each value at its C-order offset.
  const std::size_t nd = h.shape.size();
  std::vector<std::size_t> c_stride(nd, 1), index(nd, 0);
  for (std::size_t d = nd - 1; d-- > 0;) c_stride[d] = c_stride[d + 1] * h.shape[d + 1];
  std::size_t c_offset = 0;
  for (std::size_t k = 0; k < count; ++k) {
    a.data[c_offset] = toDouble(data + k * type.size, type, what);
    for (std::size_t d = 0; d < nd; ++d) {
      c_offset += c_stride[d];
      if (++index[d] < h.shape[d]) break;
      c_offset -= c_stride[d] * h.shape[d];
      index[d] = 0;
    }
  }
  return a;
}

NpyArray loadNpy(const std::string& path) {
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(support::cannotOpenMessage(path, errno));
  const std::vector<char> bytes((std::istreambuf_iterator<char>(in)),
                                std::istreambuf_iterator<char>());
  if (in.bad()) throw InputError(path + ": read error");
  return parseNpy(bytes.data(), bytes.size(), path);
}

// ---------------------------------------------------------------------------------------
// NpzArchive

struct NpzArchive::Impl {
  std::string path;
  std::string bytes;  // the archive when read from memory (fromBytes)
  zip_t* zip = nullptr;
  std::vector<std::string> names;
  std::vector<zip_uint64_t> index;  // member index of each name
  ~Impl() {
    if (zip) zipApi().discard(zip);  // read-only: nothing to write back
  }
};

namespace {
std::string zipErrorText(int code) {
  zip_error_t e;
  zipApi().error_init_with_code(&e, code);
  std::string text = zipApi().error_strerror(&e);
  zipApi().error_fini(&e);
  return text;
}
}  // namespace

NpzArchive::NpzArchive(const std::string& path) : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
  errno = 0;
  if (!std::ifstream(path).good()) throw InputError(support::cannotOpenMessage(path, errno));
  int code = 0;
  impl_->zip = zipApi().open(path.c_str(), ZIP_RDONLY | ZIP_CHECKCONS, &code);
  if (!impl_->zip) {
    throw InputError(path + ": not a readable .npz (zip) archive: " + zipErrorText(code));
  }
  listMembers();
}

NpzArchive NpzArchive::fromBytes(std::string bytes, const std::string& name) {
  NpzArchive archive;
  Impl& im = *archive.impl_;
  im.path = name;
  im.bytes = std::move(bytes);
  zip_error_t error;
  zipApi().error_init(&error);
  zip_source_t* source = zipApi().source_buffer_create(im.bytes.data(), im.bytes.size(), 0, &error);
  if (source) {
    im.zip = zipApi().open_from_source(source, ZIP_RDONLY | ZIP_CHECKCONS, &error);
    if (!im.zip) zipApi().source_free(source);
  }
  if (!im.zip) {
    const std::string text = zipApi().error_strerror(&error);
    zipApi().error_fini(&error);
    throw InputError(name + ": not a readable .npz (zip) archive: " + text);
  }
  zipApi().error_fini(&error);
  archive.listMembers();
  return archive;
}

NpzArchive::NpzArchive() : impl_(std::make_unique<Impl>()) {}

void NpzArchive::listMembers() {
  const zip_int64_t n = zipApi().get_num_entries(impl_->zip, 0);
  for (zip_int64_t i = 0; i < n; ++i) {
    const char* raw = zipApi().get_name(impl_->zip, static_cast<zip_uint64_t>(i), 0);
    if (!raw) continue;
    std::string name = raw;
    if (!name.empty() && name.back() == '/') continue;  // directory entry
    if (name.size() > 4 && name.compare(name.size() - 4, 4, ".npy") == 0)
      name.resize(name.size() - 4);
    impl_->names.push_back(name);
    impl_->index.push_back(static_cast<zip_uint64_t>(i));
  }
}

NpzArchive::~NpzArchive() = default;
NpzArchive::NpzArchive(NpzArchive&&) noexcept = default;
NpzArchive& NpzArchive::operator=(NpzArchive&&) noexcept = default;

const std::string& NpzArchive::path() const { return impl_->path; }
const std::vector<std::string>& NpzArchive::names() const { return impl_->names; }
bool NpzArchive::contains(const std::string& name) const {
  return std::find(impl_->names.begin(), impl_->names.end(), name) != impl_->names.end();
}

NpyArray NpzArchive::read(const std::string& name) const {
  const std::string what = impl_->path + ": array '" + name + "'";
  const auto it = std::find(impl_->names.begin(), impl_->names.end(), name);
  if (it == impl_->names.end()) {
    std::string known;
    for (const auto& n : impl_->names) known += (known.empty() ? "" : ", ") + n;
    fail(what, "not in the archive (it has: " + (known.empty() ? "nothing" : known) + ")");
  }
  const zip_uint64_t idx = impl_->index[static_cast<std::size_t>(it - impl_->names.begin())];
  zip_stat_t st;
  zipApi().stat_init(&st);
  if (zipApi().stat_index(impl_->zip, idx, 0, &st) != 0 || !(st.valid & ZIP_STAT_SIZE)) {
    fail(what, std::string("cannot read the member's size: ") + zipApi().strerror(impl_->zip));
  }
  zip_file_t* file = zipApi().fopen_index(impl_->zip, idx, 0);
  if (!file) fail(what, std::string("cannot open the member: ") + zipApi().strerror(impl_->zip));
  std::vector<unsigned char> bytes(static_cast<std::size_t>(st.size));
  std::string problem;
  zip_uint64_t got = 0;
  while (got < st.size) {
    const zip_int64_t r = zipApi().fread(file, bytes.data() + got, st.size - got);
    if (r < 0) {
      problem = zipApi().file_strerror(file);
      break;
    }
    if (r == 0) {
      problem =
          "member ends after " + std::to_string(got) + " of " + std::to_string(st.size) + " bytes";
      break;
    }
    got += static_cast<zip_uint64_t>(r);
  }
  if (problem.empty()) {
    // One more read reaches the end of the member, where libzip verifies the CRC-32.
    unsigned char extra = 0;
    const zip_int64_t r = zipApi().fread(file, &extra, 1);
    if (r < 0) problem = zipApi().file_strerror(file);
    if (r > 0) problem = "member is longer than its recorded size";
  }
  const int close_code = zipApi().fclose(file);
  if (problem.empty() && close_code != 0) problem = zipErrorText(close_code);
  if (!problem.empty()) fail(what, "corrupt member: " + problem);
  return parseNpy(bytes.data(), bytes.size(), what);
}

}  // namespace graphslam::io
