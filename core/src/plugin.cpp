// SPDX-License-Identifier: MIT
#include "graphslam/core/plugin.h"

#include <boost/dll/shared_library.hpp>
#include <exception>

#include "graphslam/core/error.h"

namespace graphslam {

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
  if (ec) throw Error("plugin '" + path + "': cannot load: " + ec.message());
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

}  // namespace graphslam
