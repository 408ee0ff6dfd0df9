// SPDX-License-Identifier: MIT
// Private to graphslam::solvers: keeps CHOLMOD's internal OpenMP loops serial when the
// application opted in (serializeCholmodOpenMp, graphslam/solvers/process.h).
#pragma once

namespace graphslam::solvers::detail {

/// While alive, and only when the application enabled it, OpenMP parallel regions run on
/// one thread (max-active-levels 0), if the process has an OpenMP runtime loaded. Nests
/// and is thread safe: the first guard alive saves the setting, the last restores it. A
/// guard made while disabled changes nothing, whatever happens to the switch meanwhile.
class SerialOpenMp {
 public:
  SerialOpenMp();
  ~SerialOpenMp();
  SerialOpenMp(const SerialOpenMp&) = delete;
  SerialOpenMp& operator=(const SerialOpenMp&) = delete;

  /// The application's switch (off by default).
  static void enable(bool on);
  [[nodiscard]] static bool enabled();

 private:
  bool active_ = false;
};

}  // namespace graphslam::solvers::detail
