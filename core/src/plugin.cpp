// SPDX-License-Identifier: MIT
#include "graphslam/core/plugin.h"

#include <dlfcn.h>

#include <boost/dll/shared_library.hpp>
#include <algorithm>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <sstream>

#include "graphslam/core/error.h"

namespace graphslam {

namespace {

/// The dynamic loader's own reason why `path` does not load (missing file, not a shared
/// object, unresolved symbol, ...), else `fallback`.
std::string loadFailure(const std::string& path, const std::string& fallback) {
  dlerror();  // clears an earlier message
  if (void* handle = dlopen(path.c_str(), RTLD_LAZY | RTLD_LOCAL)) {
    dlclose(handle);
    return fallback;
  }
  const char* reason = dlerror();
  return reason ? reason : fallback;
}

}  // namespace

struct Plugin::Impl {
  boost::dll::shared_library library;
};

Plugin::Plugin(std::string path, std::unique_ptr<Impl> impl)
    : path_(std::move(path)), impl_(std::move(impl)) {}

Plugin::~Plugin() = default;

std::unique_ptr<Plugin> Plugin::load(const std::string& path, TypeRegistry& types,
                                     SolverRegistry& solvers) {
  auto impl = std::make_unique<Impl>();
  boost::dll::fs::error_code ec;
  impl->library.load(path, boost::dll::load_mode::default_mode, ec);
  if (ec) throw Error("plugin '" + path + "': cannot load: " + loadFailure(path, ec.message()));
  if (!impl->library.has(GRAPHSLAM_PLUGIN_ENTRY)) {
    throw Error("plugin '" + path +
                "': no symbol '" GRAPHSLAM_PLUGIN_ENTRY "' (declare it extern \"C\")");
  }
  auto& entry = impl->library.get<PluginRegisterFunction>(GRAPHSLAM_PLUGIN_ENTRY);
  types.setOrigin(path);
  solvers.setOrigin(path);
  try {
    entry(types, solvers);
  } catch (const std::exception& ex) {
    types.setOrigin("");
    solvers.setOrigin("");
    throw Error("plugin '" + path + "': registration failed: " + ex.what());
  }
  types.setOrigin("");
  solvers.setOrigin("");
  return std::unique_ptr<Plugin>(new Plugin(path, std::move(impl)));
}

std::vector<std::string> findPluginFiles(const std::vector<std::string>& directories) {
  namespace fs = std::filesystem;
  std::vector<std::string> out;
  for (const auto& dir : directories) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) continue;
    std::vector<std::string> files;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
      const std::string name = entry.path().filename().string();
      const bool plugin_name = name.size() > 6 && name.compare(0, 3, "lib") == 0 &&
                               name.compare(name.size() - 3, 3, ".so") == 0;
      if (plugin_name && entry.is_regular_file(ec)) files.push_back(entry.path().string());
    }
    std::sort(files.begin(), files.end());
    out.insert(out.end(), files.begin(), files.end());
  }
  return out;
}

std::vector<std::string> pluginPathFromEnvironment() {
  std::vector<std::string> out;
  const char* value = std::getenv(kPluginPathVariable);
  if (!value) return out;
  std::stringstream list(value);
  std::string dir;
  while (std::getline(list, dir, ':')) {
    if (!dir.empty()) out.push_back(dir);
  }
  return out;
}

std::vector<std::unique_ptr<Plugin>> loadPlugins(const std::vector<std::string>& paths,
                                                 TypeRegistry& types, SolverRegistry& solvers) {
  std::vector<std::unique_ptr<Plugin>> out;
  for (const auto& path : paths) out.push_back(Plugin::load(path, types, solvers));
  return out;
}

}  // namespace graphslam
