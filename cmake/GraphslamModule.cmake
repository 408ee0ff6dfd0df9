# SPDX-License-Identifier: MIT
# graphslam_add_module(<name> SOURCES ... [PUBLIC_LIBS ...] [PRIVATE_LIBS ...])
# Defines library graphslam_<name> with alias graphslam::<name>, its public include
# directory <module>/include, warnings, and its install/export rules.
function(graphslam_add_module name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_LIBS;PRIVATE_LIBS" ${ARGN})
  set(target graphslam_${name})
  add_library(${target} ${ARG_SOURCES})
  add_library(graphslam::${name} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name} OUTPUT_NAME ${target})
  target_compile_features(${target} PUBLIC cxx_std_17)
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(${target} PUBLIC ${ARG_PUBLIC_LIBS} PRIVATE ${ARG_PRIVATE_LIBS} graphslam_warnings)
  install(TARGETS ${target} EXPORT graphslamTargets
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endfunction()

# graphslam_add_plugin(<name> SOURCES ... LIBS ...)
# Defines the run-time plugin graphslam_plugin_<name>: a shared module exporting the one
# entry graphslam_plugin_register, linked against the shared libraries it registers from
# (so their code exists once per process). Built into ${GRAPHSLAM_PLUGIN_BUILD_DIR} and
# installed into ${GRAPHSLAM_PLUGIN_INSTALL_DIR}, where the graphslam tool discovers it.
function(graphslam_add_plugin name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBS" ${ARGN})
  set(target graphslam_plugin_${name})
  add_library(${target} MODULE ${ARG_SOURCES})
  target_link_libraries(${target} PRIVATE ${ARG_LIBS} graphslam_warnings)
  set_target_properties(${target} PROPERTIES
    LIBRARY_OUTPUT_DIRECTORY ${GRAPHSLAM_PLUGIN_BUILD_DIR}
    # installed in <libdir>/graphslam/plugins: the libraries are two folders up
    INSTALL_RPATH "$ORIGIN/../..")
  install(TARGETS ${target} LIBRARY DESTINATION ${GRAPHSLAM_PLUGIN_INSTALL_DIR})
  set_property(GLOBAL APPEND PROPERTY GRAPHSLAM_PLUGINS ${target})
endfunction()

# graphslam_runtime_name(<var> <libraries...>)
# The name a program loads the first library file of <libraries> by at run time (its ELF
# SONAME, e.g. libopenblas.so.0), for libraries the project loads on first use with dlopen
# instead of linking; empty when none is a file.
function(graphslam_runtime_name var)
  set(${var} "" PARENT_SCOPE)
  foreach(_lib IN LISTS ARGN)
    if(EXISTS "${_lib}" AND NOT IS_DIRECTORY "${_lib}")
      get_filename_component(_real "${_lib}" REALPATH)
      execute_process(COMMAND ${CMAKE_OBJDUMP} -p "${_real}" OUTPUT_VARIABLE _dump
                      ERROR_QUIET RESULT_VARIABLE _rc)
      if(_rc EQUAL 0 AND _dump MATCHES "SONAME +([^\n ]+)")
        set(${var} "${CMAKE_MATCH_1}" PARENT_SCOPE)
      else()
        set(${var} "${_real}" PARENT_SCOPE)
      endif()
      return()
    endif()
  endforeach()
endfunction()
