// SPDX-License-Identifier: MIT
// Private to graphslam::io: libzip's functions, loaded on first use (the .npz reader is the
// only user; libzip brings libcrypto, whose loading a program that reads no .npz file
// should not pay).
#pragma once

#include <zip.h>

namespace graphslam::io::detail {

struct ZipApi {
  decltype(&::zip_discard) discard = nullptr;
  decltype(&::zip_error_fini) error_fini = nullptr;
  decltype(&::zip_error_init) error_init = nullptr;
  decltype(&::zip_error_init_with_code) error_init_with_code = nullptr;
  decltype(&::zip_error_strerror) error_strerror = nullptr;
  decltype(&::zip_fclose) fclose = nullptr;
  decltype(&::zip_file_strerror) file_strerror = nullptr;
  decltype(&::zip_fopen_index) fopen_index = nullptr;
  decltype(&::zip_fread) fread = nullptr;
  decltype(&::zip_get_name) get_name = nullptr;
  decltype(&::zip_get_num_entries) get_num_entries = nullptr;
  decltype(&::zip_open) open = nullptr;
  decltype(&::zip_open_from_source) open_from_source = nullptr;
  decltype(&::zip_source_buffer_create) source_buffer_create = nullptr;
  decltype(&::zip_source_free) source_free = nullptr;
  decltype(&::zip_stat_index) stat_index = nullptr;
  decltype(&::zip_stat_init) stat_init = nullptr;
  decltype(&::zip_strerror) strerror = nullptr;
};

/// libzip's functions, loading the library on the first call. Throws graphslam::InputError
/// when it cannot be loaded (naming it and the loader's reason).
const ZipApi& zipApi();

}  // namespace graphslam::io::detail
