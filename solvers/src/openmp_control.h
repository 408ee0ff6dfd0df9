// SPDX-License-Identifier: MIT
// Private to graphslam::solvers: keeps CHOLMOD's internal OpenMP loops serial.
#pragma once

namespace graphslam::solvers::detail {

/// While alive, OpenMP parallel regions run on one thread (max-active-levels 0), if the
/// process has an OpenMP runtime loaded; nests and is thread safe (the first guard saves
/// the setting, the last restores it). Debian's CHOLMOD asks for 4 OpenMP threads in
/// every supernode's scatter loop, whatever OMP_NUM_THREADS says; on 2 cores their
/// hand-offs made the supernodal factorisation 2-3x slower than serial (its BLAS calls
/// keep their own threads, OPENBLAS_NUM_THREADS).
class SerialOpenMp {
 public:
  SerialOpenMp();
  ~SerialOpenMp();
  SerialOpenMp(const SerialOpenMp&) = delete;
  SerialOpenMp& operator=(const SerialOpenMp&) = delete;
};

}  // namespace graphslam::solvers::detail
