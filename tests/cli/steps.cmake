# SPDX-License-Identifier: MIT
# Shared by the end-to-end CLI scripts: a fresh WORK folder; step(REGEX COMMAND...), which
# runs COMMAND in WORK and fails unless it exits 0 with stdout matching REGEX; and
# run(EXIT REGEX COMMAND...), which fails unless COMMAND exits with EXIT and its stdout and
# stderr together match REGEX.
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
function(step expect_regex)
  execute_process(COMMAND ${ARGN} WORKING_DIRECTORY "${WORK}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message("$ ${ARGN}\n${out}${err}")
  if(rc)
    message(FATAL_ERROR "exit code ${rc}")
  endif()
  if(NOT "${out}" MATCHES "${expect_regex}")
    message(FATAL_ERROR "output does not match '${expect_regex}'")
  endif()
endfunction()
function(run expect_exit expect_regex)
  execute_process(COMMAND ${ARGN} WORKING_DIRECTORY "${WORK}" RESULT_VARIABLE rc OUTPUT_VARIABLE out
                  ERROR_VARIABLE err)
  message("$ ${ARGN}\n${out}${err}")
  if(NOT rc EQUAL expect_exit)
    message(FATAL_ERROR "exit code ${rc}, expected ${expect_exit}")
  endif()
  if(NOT "${out}${err}" MATCHES "${expect_regex}")
    message(FATAL_ERROR "output does not match '${expect_regex}'")
  endif()
endfunction()
