// SPDX-License-Identifier: MIT
// Run-time plugin registering the robust kernels of graphslam_robust (nothing when the
// program has the module already).
#include "graphslam/core/plugin.h"

#include "graphslam/robust/register.h"

GRAPHSLAM_PLUGIN_ENTRY(host) {
  if (!host.claimModule("robust")) return;
  graphslam::robust::registerKernels(*host.kernels);
}
