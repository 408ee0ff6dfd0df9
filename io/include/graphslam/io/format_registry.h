// SPDX-License-Identifier: MIT
// The format registry: every file format the library reads or writes is one entry, so a new
// format is one file and one registration (registerFormats in register.h, or a plugin's
// entry through PluginHost::formats). Formats are kept per kind of data (graphs,
// trajectories, and kinds other modules define, such as DriveBot scenarios).
#pragma once

#include <functional>
#include <iosfwd>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <typeindex>
#include <vector>

#include "graphslam/core/type_registry.h"
#include "graphslam/io/g2o.h"
#include "graphslam/io/source.h"
#include "graphslam/support/error.h"

namespace graphslam::io {

/// What a reader gets besides its input.
struct ReadContext {
  /// Graphs: the types a file may name (readers create every object through it).
  const TypeRegistry* types = nullptr;
  /// Graphs: the .g2o reader's options; formats translated to .g2o text use them too.
  LoadOptions load;
  /// Format-specific choices by name (e.g. "npz-model" = "linear"); a reader documents
  /// the ones it takes and refuses values it does not know.
  std::map<std::string, std::string> choices;
};

/// What a writer gets besides the data.
struct WriteContext {
  const TypeRegistry* types = nullptr;  ///< graphs: the tags objects are written under
};

/// The type a format of data T writes (the data itself unless specialised: a graph format
/// reads a GraphFile, with what came with the graph, and writes a Graph).
template <typename T>
struct Written {
  using type = T;
};

/// One file format of data of type T.
template <typename T>
struct Format {
  std::string name;         ///< "g2o", "tum", ...: what --format options name
  std::string description;  ///< one line for listings
  /// File name endings, lower case with the dot (".g2o"); the first is the usual one.
  std::vector<std::string> extensions;
  /// Recognises the format from the first bytes of an input (Source::head); empty: only by
  /// its extensions. Called for inputs whose extension no format claims, or claimed by
  /// several.
  std::function<bool(std::string_view head)> sniff;
  /// Reads the whole input; empty: the format cannot be read. Bad data is reported by
  /// throwing graphslam::InputError naming the input (and line), or as the data's own
  /// diagnostics.
  std::function<T(Source&, const ReadContext&)> read;
  /// Reads a folder (a format whose data is several files); empty for file formats.
  std::function<T(const std::string& folder, const ReadContext&)> read_folder;
  /// Writes the data; empty: the format cannot be written. Throws graphslam::Error for
  /// data it cannot represent.
  std::function<void(const typename Written<T>::type&, std::ostream&, const WriteContext&)> write;
};

/// Formats by kind of data and name.
class FormatRegistry {
 public:
  /// Registers `format` for data of type T. Throws RegistryError on an empty or taken name
  /// (per kind of data), or neither a reader nor a writer.
  template <typename T>
  void add(Format<T> format) {
    Table<T>& t = table<T>();
    checkNew(t, format.name, format.read || format.read_folder || format.write);
    t.names.push_back(format.name);
    t.formats.push_back(std::make_unique<Format<T>>(std::move(format)));
  }
  /// The format of kind T named `name`, or null.
  template <typename T>
  [[nodiscard]] const Format<T>* find(const std::string& name) const {
    const Table<T>* t = findTable<T>();
    if (!t) return nullptr;
    for (const auto& f : t->formats) {
      if (f->name == name) return f.get();
    }
    return nullptr;
  }
  /// The formats of kind T in registration order.
  template <typename T>
  [[nodiscard]] std::vector<const Format<T>*> formats() const {
    std::vector<const Format<T>*> out;
    if (const Table<T>* t = findTable<T>()) {
      for (const auto& f : t->formats) out.push_back(f.get());
    }
    return out;
  }
  /// The readable format of kind T for `source`: by the extension of its name when exactly
  /// one format claims it and has no sniff or its sniff agrees; otherwise the first whose
  /// sniff accepts the input's head; otherwise the one named `fallback`. Throws InputError
  /// naming the input when none fits.
  template <typename T>
  [[nodiscard]] const Format<T>& detect(Source& source, const std::string& fallback = {}) const {
    std::vector<const Format<T>*> readable;
    for (const Format<T>* f : formats<T>()) {
      if (f->read) readable.push_back(f);
    }
    return *readable.at(detectIndex(
        source, readable.size(),
        [&](std::size_t i) -> const std::vector<std::string>& { return readable[i]->extensions; },
        [&](std::size_t i, std::string_view head) {
          return readable[i]->sniff && readable[i]->sniff(head);
        },
        [&](std::size_t i) -> const std::string& { return readable[i]->name; }, fallback));
  }
  /// The writable format of kind T for an output path, by its extension; null when none
  /// claims it.
  template <typename T>
  [[nodiscard]] const Format<T>* forOutput(const std::string& path) const {
    for (const Format<T>* f : formats<T>()) {
      if (f->write && hasExtension(path, f->extensions)) return f;
    }
    return nullptr;
  }

  /// Whether `path` ends in one of `extensions` (case-insensitive).
  [[nodiscard]] static bool hasExtension(const std::string& path,
                                         const std::vector<std::string>& extensions);

 private:
  struct TableBase {
    virtual ~TableBase() = default;
    std::vector<std::string> names;
  };
  template <typename T>
  struct Table final : TableBase {
    std::vector<std::unique_ptr<Format<T>>> formats;
  };
  template <typename T>
  Table<T>& table() {
    auto& slot = tables_[std::type_index(typeid(T))];
    if (!slot) slot = std::make_unique<Table<T>>();
    return static_cast<Table<T>&>(*slot);
  }
  template <typename T>
  const Table<T>* findTable() const {
    const auto it = tables_.find(std::type_index(typeid(T)));
    return it == tables_.end() ? nullptr : static_cast<const Table<T>*>(it->second.get());
  }
  static void checkNew(const TableBase& table, const std::string& name, bool usable);
  static std::size_t detectIndex(
      Source& source, std::size_t count,
      const std::function<const std::vector<std::string>&(std::size_t)>& extensions,
      const std::function<bool(std::size_t, std::string_view)>& sniff,
      const std::function<const std::string&(std::size_t)>& name, const std::string& fallback);

  std::map<std::type_index, std::unique_ptr<TableBase>> tables_;
};

}  // namespace graphslam::io
