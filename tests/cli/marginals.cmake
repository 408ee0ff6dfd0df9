# SPDX-License-Identifier: MIT
# graphslam optimize --marginals on a small DriveBot graph whose covariances of two
# vertices are exact in binary: checks the file's layout and values, the tag filter, and
# that the fixed vertex is left out.
#   cmake -DTOOL=graphslam -DDATA=tests/data -DWORK=dir -P marginals.cmake
file(MAKE_DIRECTORY "${WORK}")
set(out "${WORK}/marginals.txt")
file(REMOVE "${out}")

function(run)
  execute_process(COMMAND "${TOOL}" ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE o ERROR_VARIABLE e)
  message("${o}${e}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "exit code ${rc}: ${ARGN}")
  endif()
endfunction()

function(expect_lines file)
  file(STRINGS "${file}" lines)
  list(LENGTH lines n)
  list(LENGTH ARGN want)
  if(NOT n EQUAL want)
    message(FATAL_ERROR "${file}: ${n} lines, expected ${want}:\n${lines}")
  endif()
  math(EXPR last "${n} - 1")
  foreach(i RANGE 0 ${last})
    list(GET lines ${i} got)
    list(GET ARGN ${i} expected)
    if(NOT got MATCHES "${expected}")
      message(FATAL_ERROR "${file}: line ${i} is '${got}', expected to match '${expected}'")
    endif()
  endforeach()
endfunction()

run(optimize "${DATA}/drivebot_small.g2o" --marginals "${out}")
# Header, then the non-fixed vertices 1 2 3 9 20 in id order; 9 (prior only) and 20
# (landmark seen once from the fixed vertex) are exact.
expect_lines("${out}" "^# graphslam marginal covariances" "^1( [-0-9.e]+)+$" "^2( [-0-9.e]+)+$"
             "^3( [-0-9.e]+)+$" "^9 0.25 0 0 0.0625 0 0.015625$" "^20 0.25 0 0.25$")
file(STRINGS "${out}" lines)
list(GET lines 1 first)
separate_arguments(values UNIX_COMMAND "${first}")
list(LENGTH values count)
if(NOT count EQUAL 7)
  message(FATAL_ERROR "vertex 1: ${count} tokens, expected id + 6 (upper triangle of 3x3)")
endif()

run(optimize "${DATA}/drivebot_small.g2o" --marginals "${out}" --marginals-tag VERTEX_LANDMARK)
expect_lines("${out}" "^#" "^20 0.25 0 0.25$")
file(GLOB leftovers "${out}.tmp.*")
if(leftovers)
  message(FATAL_ERROR "temporary files left behind: ${leftovers}")
endif()
