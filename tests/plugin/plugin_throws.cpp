// SPDX-License-Identifier: MIT
// A plugin whose registration throws something that is not a std::exception: the loader
// reports it as an error naming the file instead of ending the process.
#include "graphslam/core/plugin.h"

GRAPHSLAM_PLUGIN_ENTRY(host) {
  (void)host;
  throw 42;
}
