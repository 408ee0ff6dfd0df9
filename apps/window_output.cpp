// SPDX-License-Identifier: MIT
#include "window_output.h"

#include <cmath>
#include <filesystem>

#include "cli_common.h"
#include "graphslam/support/error.h"
#include "graphslam/support/file_util.h"

namespace graphslam::apps {

MarginalisedOut::MarginalisedOut(std::string path, const TypeRegistry& types)
    : path_(std::move(path)), types_(types) {}

void MarginalisedOut::attach(incremental::WindowOptions& window) {
  if (path_.empty()) return;
  window.on_marginalised = [this](const Vertex& v, const incremental::WindowState*) { write(v); };
}

void MarginalisedOut::start() {
  if (path_.empty()) return;
  out_.open(path_, std::ios::binary | std::ios::trunc);
  if (!out_) throw InputError(path_ + ": cannot write the marginalised vertices");
}

std::string MarginalisedOut::note() {
  if (path_.empty()) return "0";
  out_.flush();
  if (!out_) throw Error(path_ + ": writing the marginalised vertices failed");
  return std::to_string(static_cast<long long>(out_.tellp()));
}

void MarginalisedOut::resume(const std::string& note) {
  if (path_.empty()) return;
  std::uintmax_t length = 0;
  try {
    length = std::stoull(note);
  } catch (const std::exception&) {
    throw InputError("the checkpoint holds no length of the --marginalised-out file");
  }
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path_, ec);
  if (ec || size < length) {
    throw InputError(path_ + ": shorter than when the checkpoint was written (" +
                     std::to_string(length) + " bytes): not the file of that run");
  }
  std::filesystem::resize_file(path_, length);
  out_.open(path_, std::ios::binary | std::ios::app);
  if (!out_) throw InputError(path_ + ": cannot append the marginalised vertices");
}

void MarginalisedOut::write(const Vertex& v) {
  const std::string* tag = types_.tagOf(v);
  std::string line = tag ? *tag : std::string("UNKNOWN");
  line += ' ';
  line += std::to_string(v.id());
  std::vector<double> data(static_cast<std::size_t>(v.estimateDataDimension()));
  v.getEstimateData(data.data());
  for (double x : data) support::appendDouble(line, x);
  data.assign(static_cast<std::size_t>(v.parameterDataDimension()), 0.0);
  v.getParameterData(data.data());
  for (double x : data) support::appendDouble(line, x);
  line += '\n';
  out_ << line;
}

void addWindowOptions(po::options_description& desc, incremental::WindowOptions& window,
                      std::string& marginalised_out, const std::string& states) {
  desc.add_options()(
      "window", po::value(&window.states)->default_value(0),
      ("fixed-lag smoothing: keep the newest N " + states +
       ", marginalise older ones and the landmarks only they see (0: the full history)")
          .c_str())(
      "window-slack", po::value(&window.slack)->default_value(0),
      "with --window N: marginalise only when the window exceeds N + this, then down to N "
      "(the window is eliminated afresh after each marginalisation: once every this-many "
      "steps instead of at every one)")(
      "window-seconds", doubleValue(&window.seconds, 0.0),
      ("fixed-lag smoothing by time: keep the " + states +
       " within S seconds of the newest (they need time stamps, as VERTEX_VEHICLE's; 0: off)")
          .c_str())(
      "marginalised-out", po::value(&marginalised_out),
      "append every marginalised vertex to this file as it leaves the window (.g2o vertex "
      "lines: tag, id, estimate, line parameters)")(
      "reinitialise-landmarks", po::bool_switch(&window.reinitialize_landmarks),
      "with a window: a marginalised landmark seen again is added anew, placed by that "
      "observation (default: its observations are refused like edges to marginalised "
      "states)")("keep-landmarks", po::bool_switch(&window.keep_landmarks),
                 ("with a window: landmarks never leave, only " + states +
                  " (the map stays whole and a landmark seen again closes the loop; memory "
                  "then grows with the landmarks, not with the drive)")
                     .c_str());
}

void checkWindowOptions(const incremental::WindowOptions& window,
                        const std::string& marginalised_out) {
  if (!(window.seconds >= 0 && std::isfinite(window.seconds))) {
    throw UsageError("--window-seconds must be a finite number >= 0 (0: off)");
  }
  if (!window.enabled() && (!marginalised_out.empty() || window.reinitialize_landmarks ||
                            window.keep_landmarks || window.slack > 0)) {
    throw UsageError(
        "--marginalised-out, --window-slack, --reinitialise-landmarks and --keep-landmarks "
        "need --window or --window-seconds");
  }
  if (window.reinitialize_landmarks && window.keep_landmarks) {
    throw UsageError(
        "--reinitialise-landmarks and --keep-landmarks exclude each other (a kept landmark "
        "never leaves)");
  }
}

}  // namespace graphslam::apps
