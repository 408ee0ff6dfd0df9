// SPDX-License-Identifier: MIT
// A plugin built for the first plugin ABI (the unversioned entry that took the type and
// solver registries by reference): a graphslam of another ABI must refuse it by name,
// without calling it.
#include <cstdlib>

extern "C" __attribute__((visibility("default"))) void graphslam_plugin_register(void*, void*) {
  std::abort();  // never called
}
