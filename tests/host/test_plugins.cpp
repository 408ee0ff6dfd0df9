// SPDX-License-Identifier: MIT
// The plugin contract: the versioned entry, refusal of other ABIs naming both versions,
// registration failures of any kind as errors, a file loaded once, built-in modules
// registered once however often they are offered.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "graphslam/core/plugin.h"
#include "graphslam/host/registries.h"
#include "graphslam/io/graph_file.h"
#include "graphslam/support/error.h"

using namespace graphslam;

namespace {

std::string pluginPath(const char* name) {
  return std::string(GRAPHSLAM_TEST_PLUGIN_DIR) + "/lib" + name + ".so";
}

/// The message of the graphslam::Error `f` throws, or "" when it throws none.
template <typename F>
std::string errorOf(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return {};
}

}  // namespace

TEST(Host_Plugins, EntryNameCarriesTheAbi) {
  EXPECT_EQ(pluginEntrySymbol(kPluginAbiVersion),
            "graphslam_plugin_register_abi" + std::to_string(kPluginAbiVersion));
}

TEST(Host_Plugins, PluginOfTheCurrentAbiRegistersItsTypes) {
  host::Registries reg;
  host::registerBuiltins(reg);
  host::loadPlugins(reg, {pluginPath("graphslam_test_plugin")});
  EXPECT_TRUE(reg.types.contains("EDGE_SE2_RANGE"));
  EXPECT_EQ(reg.types.find("EDGE_SE2_RANGE")->origin, pluginPath("graphslam_test_plugin"));
}

TEST(Host_Plugins, OtherAbisAreRefusedNamingBothVersions) {
  host::Registries reg;
  const std::string old_abi =
      errorOf([&] { host::loadPlugins(reg, {pluginPath("graphslam_test_plugin_old_abi")}); });
  EXPECT_NE(old_abi.find("built for plugin ABI 1, this graphslam has plugin ABI " +
                         std::to_string(kPluginAbiVersion)),
            std::string::npos)
      << old_abi;
  const std::string future =
      errorOf([&] { host::loadPlugins(reg, {pluginPath("graphslam_test_plugin_future_abi")}); });
  EXPECT_NE(future.find("built for plugin ABI 99, this graphslam has plugin ABI " +
                        std::to_string(kPluginAbiVersion)),
            std::string::npos)
      << future;
  EXPECT_TRUE(reg.plugins.empty());
}

TEST(Host_Plugins, ANonStdExceptionIsAnError) {
  host::Registries reg;
  const std::string message =
      errorOf([&] { host::loadPlugins(reg, {pluginPath("graphslam_test_plugin_throws")}); });
  EXPECT_NE(message.find("registration failed: it threw an exception that is not a "
                         "std::exception"),
            std::string::npos)
      << message;
}

TEST(Host_Plugins, AFileIsLoadedOnceWhateverItsPath) {
  host::Registries reg;
  host::registerBuiltins(reg);
  const std::string path = pluginPath("graphslam_test_plugin");
  const std::string other =
      std::string(GRAPHSLAM_TEST_PLUGIN_DIR) + "/./libgraphslam_test_plugin.so";
  host::loadPlugins(reg, {path, other, path});
  EXPECT_EQ(reg.plugins.size(), 1u);
}

TEST(Host_Plugins, BuiltInModulesRegisterOnce) {
  host::Registries reg;
  host::registerBuiltins(reg);
  const std::size_t types = reg.types.entries().size();
  host::registerBuiltins(reg);
  EXPECT_EQ(reg.types.entries().size(), types);
  EXPECT_TRUE(reg.types.contains("VERTEX_SE2"));
  EXPECT_TRUE(reg.kernels.contains("huber"));
  EXPECT_TRUE(reg.solvers.contains("auto"));
  EXPECT_NE(reg.formats.find<io::GraphFile>("g2o"), nullptr);
}

TEST(Host_Plugins, MissingAndGarbageFilesNameTheReason) {
  host::Registries reg;
  EXPECT_NE(errorOf([&] {
              host::loadPlugins(reg, {"/nonexistent/libnothing.so"});
            }).find("plugin '/nonexistent/libnothing.so': cannot load: "),
            std::string::npos);
}
