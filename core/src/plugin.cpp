// SPDX-License-Identifier: MIT
#include "graphslam/core/plugin.h"

#include <dlfcn.h>
#include <sys/stat.h>

#include <algorithm>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <sstream>

#include "graphslam/support/error.h"

namespace graphslam {

namespace {

/// The highest plugin ABI a foreign plugin is looked for under (its entry's name).
constexpr std::uint32_t kHighestAbiProbed = 128;

/// The symbol of the entry before the ABI was versioned (ABI 1).
constexpr const char* kAbi1Entry = "graphslam_plugin_register";

/// The ABI a library was built for when it is not ours: 1 for the unversioned entry, N for
/// graphslam_plugin_register_abiN; 0 when it has no graphslam entry at all.
std::uint32_t foreignAbi(void* handle) {
  for (std::uint32_t abi = 2; abi <= kHighestAbiProbed; ++abi) {
    if (abi != kPluginAbiVersion && dlsym(handle, pluginEntrySymbol(abi).c_str()) != nullptr) {
      return abi;
    }
  }
  return dlsym(handle, kAbi1Entry) != nullptr ? 1 : 0;
}

/// "DEVICE:INODE" of the file at `path`, or the path itself when it cannot be read.
std::string fileIdentity(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return path;
  return std::to_string(static_cast<unsigned long long>(st.st_dev)) + ":" +
         std::to_string(static_cast<unsigned long long>(st.st_ino));
}

/// Calls the entry, turning every exception (std or not) into graphslam::Error.
void callEntry(PluginEntryFunction* entry, const PluginHost& host, const std::string& path) {
  host.setOrigin(path);
  try {
    entry(host);
  } catch (const std::exception& ex) {
    host.setOrigin("");
    throw Error("plugin '" + path + "': registration failed: " + ex.what());
  } catch (...) {
    host.setOrigin("");
    throw Error("plugin '" + path +
                "': registration failed: it threw an exception that is not "
                "a std::exception");
  }
  host.setOrigin("");
}

}  // namespace

std::string pluginEntrySymbol(std::uint32_t abi) {
  return "graphslam_plugin_register_abi" + std::to_string(abi);
}

void PluginHost::setOrigin(const std::string& origin) const {
  if (types) types->setOrigin(origin);
  if (solvers) solvers->setOrigin(origin);
  if (kernels) kernels->setOrigin(origin);
}

Plugin::Plugin(std::string path, std::string identity, void* handle)
    : path_(std::move(path)), identity_(std::move(identity)), handle_(handle) {}

Plugin::~Plugin() {
  if (handle_) dlclose(handle_);
}

std::unique_ptr<Plugin> Plugin::load(const std::string& path, const PluginHost& host) {
  if (host.abi_version != kPluginAbiVersion) {
    throw Error("plugin '" + path + "': the program's PluginHost says ABI " +
                std::to_string(host.abi_version) + ", this library is ABI " +
                std::to_string(kPluginAbiVersion));
  }
  dlerror();  // clears an earlier message
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* reason = dlerror();
    throw Error("plugin '" + path + "': cannot load: " + (reason ? reason : "unknown reason"));
  }
  // Owned from here: closed on every error below.
  std::unique_ptr<Plugin> plugin(new Plugin(path, fileIdentity(path), handle));
  const std::string symbol = pluginEntrySymbol(kPluginAbiVersion);
  auto* entry = reinterpret_cast<PluginEntryFunction*>(dlsym(handle, symbol.c_str()));
  if (!entry) {
    const std::uint32_t abi = foreignAbi(handle);
    if (abi != 0) {
      throw Error("plugin '" + path + "': built for plugin ABI " + std::to_string(abi) +
                  ", this graphslam has plugin ABI " + std::to_string(kPluginAbiVersion) +
                  ": rebuild the plugin against this version's headers");
    }
    throw Error("plugin '" + path + "': not a graphslam plugin (no symbol '" + symbol +
                "': define it with GRAPHSLAM_PLUGIN_ENTRY)");
  }
  callEntry(entry, host, path);
  return plugin;
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

void loadPlugins(const std::vector<std::string>& paths, const PluginHost& host,
                 std::vector<std::unique_ptr<Plugin>>& plugins) {
  for (const auto& path : paths) {
    const std::string identity = fileIdentity(path);
    const bool loaded = std::any_of(plugins.begin(), plugins.end(),
                                    [&](const auto& p) { return p->identity() == identity; });
    if (!loaded) plugins.push_back(Plugin::load(path, host));
  }
}

}  // namespace graphslam
