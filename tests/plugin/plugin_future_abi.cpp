// SPDX-License-Identifier: MIT
// A plugin built for a later plugin ABI (99): refused by name, never called.
#include <cstdlib>

extern "C" __attribute__((visibility("default"))) void graphslam_plugin_register_abi99(
    const void*) {
  std::abort();  // never called
}
