# SPDX-License-Identifier: MIT
# The API reference: target `docs` runs Doxygen (Debian: apt-get install doxygen) on the public
# headers of every module (<module>/include/graphslam/) into <build>/docs/api/html and fails
# when Doxygen wrote any warning (the log is printed). Defined only when Doxygen is found.
#
# Also run as a script (cmake -DLOG=FILE -P cmake/Docs.cmake): the warning check itself.
if(CMAKE_SCRIPT_MODE_FILE)
  if(NOT EXISTS "${LOG}")
    message(FATAL_ERROR "docs: Doxygen wrote no warning log (${LOG}); did it run?")
  endif()
  file(READ "${LOG}" _warnings)
  string(STRIP "${_warnings}" _warnings)
  if(NOT _warnings STREQUAL "")
    string(REGEX MATCHALL "warning:" _count "${_warnings}")
    list(LENGTH _count _n)
    message(FATAL_ERROR "docs: Doxygen reported ${_n} warning(s) (${LOG}):\n${_warnings}")
  endif()
  message(STATUS "docs: no Doxygen warnings")
  return()
endif()

find_package(Doxygen QUIET)
if(NOT DOXYGEN_FOUND)
  message(STATUS "graphslam: Doxygen not found, no 'docs' target (apt-get install doxygen)")
  return()
endif()

set(GRAPHSLAM_DOCS_OUTPUT ${PROJECT_BINARY_DIR}/docs/api)
set(GRAPHSLAM_DOCS_INPUT "")
set(GRAPHSLAM_DOCS_INCLUDE_DIRS "")
foreach(_module IN LISTS GRAPHSLAM_MODULES)
  set(_dir ${PROJECT_SOURCE_DIR}/${_module}/include)
  if(IS_DIRECTORY ${_dir}/graphslam)
    string(APPEND GRAPHSLAM_DOCS_INPUT " \"${_dir}/graphslam\"")
    string(APPEND GRAPHSLAM_DOCS_INCLUDE_DIRS " \"${_dir}\"")
  endif()
endforeach()
string(APPEND GRAPHSLAM_DOCS_INPUT " \"${PROJECT_SOURCE_DIR}/docs/api/mainpage.md\"")
configure_file(${PROJECT_SOURCE_DIR}/docs/api/Doxyfile.in ${GRAPHSLAM_DOCS_OUTPUT}/Doxyfile @ONLY)

add_custom_target(docs
  COMMAND Doxygen::doxygen ${GRAPHSLAM_DOCS_OUTPUT}/Doxyfile
  COMMAND ${CMAKE_COMMAND} -DLOG=${GRAPHSLAM_DOCS_OUTPUT}/warnings.log
          -P ${PROJECT_SOURCE_DIR}/cmake/Docs.cmake
  WORKING_DIRECTORY ${GRAPHSLAM_DOCS_OUTPUT}
  SOURCES ${PROJECT_SOURCE_DIR}/docs/api/Doxyfile.in ${PROJECT_SOURCE_DIR}/docs/api/mainpage.md
  COMMENT "API reference (Doxygen): ${GRAPHSLAM_DOCS_OUTPUT}/html/index.html"
  VERBATIM)
