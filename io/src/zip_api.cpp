// SPDX-License-Identifier: MIT
#include "zip_api.h"

#include <dlfcn.h>

#include <string>

#include "graphslam/support/error.h"

namespace graphslam::io::detail {

namespace {

template <typename F>
void resolve(F& f, void* handle, const char* symbol) {
  f = reinterpret_cast<F>(dlsym(handle, symbol));
  if (!f) throw InputError(std::string("the zip library lacks ") + symbol + " (.npz files)");
}

ZipApi load() {
  // Kept loaded for the process's lifetime (the handle is never closed).
  void* handle = dlopen(GRAPHSLAM_LIBZIP_RUNTIME, RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* why = dlerror();
    throw InputError(std::string("reading .npz files needs libzip (") + GRAPHSLAM_LIBZIP_RUNTIME +
                     "): " + (why ? why : "cannot load it"));
  }
  ZipApi api;
  resolve(api.discard, handle, "zip_discard");
  resolve(api.error_fini, handle, "zip_error_fini");
  resolve(api.error_init, handle, "zip_error_init");
  resolve(api.error_init_with_code, handle, "zip_error_init_with_code");
  resolve(api.error_strerror, handle, "zip_error_strerror");
  resolve(api.fclose, handle, "zip_fclose");
  resolve(api.file_strerror, handle, "zip_file_strerror");
  resolve(api.fopen_index, handle, "zip_fopen_index");
  resolve(api.fread, handle, "zip_fread");
  resolve(api.get_name, handle, "zip_get_name");
  resolve(api.get_num_entries, handle, "zip_get_num_entries");
  resolve(api.open, handle, "zip_open");
  resolve(api.open_from_source, handle, "zip_open_from_source");
  resolve(api.source_buffer_create, handle, "zip_source_buffer_create");
  resolve(api.source_free, handle, "zip_source_free");
  resolve(api.stat_index, handle, "zip_stat_index");
  resolve(api.stat_init, handle, "zip_stat_init");
  resolve(api.strerror, handle, "zip_strerror");
  return api;
}

}  // namespace

const ZipApi& zipApi() {
  static const ZipApi api = load();  // thread-safe initialisation; retried after a throw
  return api;
}

}  // namespace graphslam::io::detail
