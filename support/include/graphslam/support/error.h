// SPDX-License-Identifier: MIT
#pragma once

#include <stdexcept>
#include <string>
#include <typeinfo>

namespace graphslam {

/// Base of every exception graphslam throws: API misuse or unusable input
/// (numerical outcomes are reported through status enums, never thrown).
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A registry refused a registration (duplicate tag, whitespace in a tag, null factory)
/// or was asked for a name it does not know.
class RegistryError : public Error {
 public:
  using Error::Error;
};

/// Input data could not be used; the message has the form `FILE:LINE: what is wrong`
/// whenever a file and line are known.
class InputError : public Error {
 public:
  using Error::Error;
};

/// The C++ name of `type` as written in code (demangled), for messages about types that no
/// registry names (a .g2o tag is the better name where there is one).
[[nodiscard]] std::string typeName(const std::type_info& type);

}  // namespace graphslam
