// SPDX-License-Identifier: MIT
#include "graphslam/io/format_registry.h"

#include <algorithm>
#include <cctype>

namespace graphslam::io {

bool FormatRegistry::hasExtension(const std::string& path,
                                  const std::vector<std::string>& extensions) {
  return std::any_of(extensions.begin(), extensions.end(), [&](const std::string& ext) {
    return path.size() >= ext.size() &&
           std::equal(ext.rbegin(), ext.rend(), path.rbegin(), [](char a, char b) {
             return std::tolower(static_cast<unsigned char>(a)) ==
                    std::tolower(static_cast<unsigned char>(b));
           });
  });
}

void FormatRegistry::checkNew(const TableBase& table, const std::string& name, bool usable) {
  if (name.empty()) throw RegistryError("empty format name");
  if (!usable) throw RegistryError("format '" + name + "' has neither a reader nor a writer");
  if (std::find(table.names.begin(), table.names.end(), name) != table.names.end()) {
    throw RegistryError("format '" + name + "' is already registered");
  }
}

std::size_t FormatRegistry::detectIndex(
    Source& source, std::size_t count,
    const std::function<const std::vector<std::string>&(std::size_t)>& extensions,
    const std::function<bool(std::size_t, std::string_view)>& sniff,
    const std::function<const std::string&(std::size_t)>& name, const std::string& fallback) {
  std::vector<std::size_t> claimed;
  for (std::size_t i = 0; i < count; ++i) {
    if (hasExtension(source.name(), extensions(i))) claimed.push_back(i);
  }
  const std::string_view head = source.head();
  // A format claiming the extension whose sniff agrees (or that has none) reads it; the
  // content decides among formats sharing an extension and for unclaimed ones.
  for (std::size_t i : claimed) {
    if (sniff(i, head)) return i;
  }
  if (claimed.size() == 1) return claimed[0];
  for (std::size_t i = 0; i < count; ++i) {
    if (sniff(i, head)) return i;
  }
  for (std::size_t i = 0; i < count; ++i) {
    if (name(i) == fallback) return i;
  }
  throw InputError(source.name() + ": cannot tell its format from its name or its first bytes");
}

}  // namespace graphslam::io
