# SPDX-License-Identifier: MIT
# Installs the build tree into a scratch prefix and imports the installed Python package
# from there (its extension finding the installed libraries by its relative RPATH), then
# optimises a small simulated graph with it.
#   cmake -DBUILD_DIR=... -DWORK_DIR=... -DPYTHON=... -DPY_DIR=... -P run_installed.cmake
file(REMOVE_RECURSE "${WORK_DIR}")
execute_process(COMMAND ${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${WORK_DIR}/prefix"
                RESULT_VARIABLE rc OUTPUT_QUIET)
if(rc)
  message(FATAL_ERROR "install failed (${rc})")
endif()
set(site "${WORK_DIR}/prefix/${PY_DIR}")
if(NOT EXISTS "${site}/graphslam/__init__.py")
  message(FATAL_ERROR "the package is not installed in ${site}")
endif()
set(ENV{PYTHONPATH} "${site}")
execute_process(COMMAND ${PYTHON} -c
  "import graphslam, sys; assert graphslam.__file__.startswith(sys.argv[1]), graphslam.__file__; s = graphslam.simulate_manhattan(num_poses=100); r = graphslam.optimize(s.graph); assert r.ok, r.message; print('installed graphslam', graphslam.__version__, r.status, r.final_chi2)"
  "${site}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(rc)
  message(FATAL_ERROR "the installed package failed (${rc})")
endif()
