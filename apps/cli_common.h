// SPDX-License-Identifier: MIT
// Helpers shared by the graphslam tool's subcommands.
#pragma once

#include <boost/program_options.hpp>
#include <cerrno>
#include <charconv>
#include <cstdlib>
#include <initializer_list>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "builtins.h"
#include "graphslam/core/plugin.h"
#include "graphslam/host/registries.h"
#include "graphslam/optimizer/optimizer.h"

namespace graphslam::apps {

namespace po = boost::program_options;

constexpr int kExitOk = 0;
constexpr int kExitFailed = 1;    // the optimisation did not succeed
constexpr int kExitBadInput = 2;  // bad arguments or input data

/// Thrown for bad command-line use; main prints it with the subcommand's usage hint.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The tool's registries: the library's modules, then the plugins of GRAPHSLAM_PLUGIN_PATH
/// and --plugin.
using Registries = host::Registries;

inline void loadRegistries(Registries& r, const std::vector<std::string>& plugins) {
  host::registerBuiltins(r);
  host::loadPlugins(r, plugins);
}

/// program_options' "the argument ('V') for option '--x' is invalid", saying "is out of
/// range" instead when V is a number the option's type cannot hold (an integer beyond an
/// int, 1e400).
inline std::string invalidValueMessage(const std::string& what) {
  const std::size_t open = what.find("('"), close = what.find("')"), at = what.rfind(" is invalid");
  if (open == std::string::npos || close == std::string::npos || close < open ||
      at == std::string::npos) {
    return what;
  }
  const std::string value = what.substr(open + 2, close - open - 2);
  errno = 0;
  char* end = nullptr;
  std::strtod(value.c_str(), &end);
  const bool number = !value.empty() && end == value.c_str() + value.size();
  const bool integer = number && value.find_first_not_of("+-0123456789") == std::string::npos;
  if (!integer && !(number && errno == ERANGE)) return what;
  return what.substr(0, at) + " is out of range" + what.substr(at + 11);
}

inline po::variables_map parse(const std::vector<std::string>& args,
                               const po::options_description& desc,
                               const po::positional_options_description* pos = nullptr) {
  po::variables_map vm;
  auto parser = po::command_line_parser(args).options(desc);
  if (pos) parser.positional(*pos);
  try {
    po::store(parser.run(), vm);
  } catch (const po::invalid_option_value& e) {
    throw UsageError(invalidValueMessage(e.what()));
  }
  po::notify(vm);
  return vm;
}

/// The value of `option` among `choices` (name, value); otherwise a UsageError
/// "--option must be a, b or c, not 'value'".
template <typename T>
T parseChoice(const std::string& option, const std::string& value,
              std::initializer_list<std::pair<const char*, T>> choices) {
  std::string names;
  std::size_t k = 0;
  for (const auto& [name, v] : choices) {
    if (value == name) return v;
    names += (k == 0 ? "" : (k + 1 == choices.size() ? " or " : ", ")) + std::string(name);
    ++k;
  }
  throw UsageError("--" + option + " must be " + names + ", not '" + value + "'");
}

/// `text` with its control bytes (an ESC in a file name, say) shown as \xNN, so that a
/// message never sends a terminal escape sequence; line ends and tabs are kept.
inline std::string printable(const std::string& text) {
  static const char* hex = "0123456789abcdef";
  std::string out;
  out.reserve(text.size());
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if ((c < 0x20 && c != '\n' && c != '\t') || c == 0x7f) {
      out += "\\x";
      out += hex[c >> 4];
      out += hex[c & 15];
    } else {
      out += ch;
    }
  }
  return out;
}

/// po::value(target) with `value` as its default, shown in --help in its shortest exact
/// form (1e-12, 0.1) rather than boost's 17 digits (9.9999999999999998e-13).
inline po::typed_value<double>* doubleValue(double* target, double value) {
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, value).ptr;
  return po::value(target)->default_value(value, std::string(text, end));
}

/// Throws UsageError saying why --solver `spec` cannot be used: an unknown solver (the
/// known ones listed) or an ordering the solver does not offer (its orderings listed).
inline void checkSolverSpec(const std::string& spec, const SolverRegistry& solvers) {
  if (solvers.contains(spec)) return;
  try {
    (void)solvers.create(spec);
  } catch (const Error& e) {
    throw UsageError(std::string("--solver: ") + e.what());
  }
  throw UsageError("--solver: unknown solver '" + spec +
                   "' (graphslam list-solvers shows the known ones)");
}

inline Algorithm parseAlgorithm(const std::string& value) {
  return parseChoice<Algorithm>("algorithm", value,
                                {{"auto", Algorithm::kGaussNewtonFallback},
                                 {"gn", Algorithm::kGaussNewton},
                                 {"lm", Algorithm::kLevenbergMarquardt},
                                 {"dogleg", Algorithm::kDogleg}});
}

inline void printHelp(const char* usage, const po::options_description& desc) {
  std::cout << usage << "\n\n" << desc << "\n";
}

/// Parses the options of the listing commands (only --plugin); returns false after --help.
inline bool parseListing(const std::vector<std::string>& args, const char* usage, Registries& reg) {
  std::vector<std::string> plugins;
  po::options_description desc("options");
  desc.add_options()("help,h", "show this help")("plugin", po::value(&plugins)->composing(),
                                                 "also load this plugin (repeatable)");
  const auto vm = parse(args, desc);
  if (vm.count("help")) {
    printHelp(usage, desc);
    return false;
  }
  loadRegistries(reg, plugins);
  return true;
}

// Subcommands implemented outside graphslam.cpp.
int cmdEval(const std::vector<std::string>& args);
int cmdDeadreckon(const std::vector<std::string>& args);
int cmdConvert(const std::vector<std::string>& args);
int cmdInfo(const std::vector<std::string>& args);
int cmdDrivebot(const std::vector<std::string>& args);
int cmdSolvers(const std::vector<std::string>& args);
int cmdAddOutliers(const std::vector<std::string>& args);
int cmdSimulate(const std::vector<std::string>& args);
int cmdCalibrate(const std::vector<std::string>& args);
int cmdListTypes(const std::vector<std::string>& args);
int cmdListSolvers(const std::vector<std::string>& args);
int cmdIncremental(const std::vector<std::string>& args);
int cmdView(const std::vector<std::string>& args);

}  // namespace graphslam::apps
