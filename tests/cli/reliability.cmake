# SPDX-License-Identifier: MIT
# Messages and refusals of the second reliability pass, each with the exit code it must
# give: a control byte in a file name is shown escaped; KITTI files of different lengths
# name both counts; info refuses pictures that would overwrite its input or each other;
# --reject-outliers' robust initialisation on a 3D graph says it places 2D graphs only;
# incremental takes -q; --help prints defaults in their shortest form; a zero quaternion is
# refused at its line. Usage: cmake -DTOOL=graphslam -DWORK=dir -P reliability.cmake
include(${CMAKE_CURRENT_LIST_DIR}/steps.cmake)

string(ASCII 27 esc)
run(2 "cannot open" "${TOOL}" optimize "missing${esc}x.g2o")
# The raw byte must not reach the terminal: the message shows \x1b instead.
execute_process(COMMAND "${TOOL}" optimize "missing${esc}x.g2o" ERROR_VARIABLE err OUTPUT_QUIET
                RESULT_VARIABLE rc)
string(FIND "${err}" "${esc}" raw)
if(NOT raw EQUAL -1 OR NOT err MATCHES "missing\\\\x1bx[.]g2o")
  message(FATAL_ERROR "the ESC byte was echoed raw: ${err}")
endif()

file(WRITE "${WORK}/a.kitti" "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 1 0 1 0 0 0 0 1 0\n")
file(WRITE "${WORK}/b.kitti" "1 0 0 0 0 1 0 0 0 0 1 0\n")
run(2 "KITTI trajectories have no timestamps.*a[.]kitti has 2, b[.]kitti has 1"
    "${TOOL}" eval ape a.kitti b.kitti)

file(WRITE "${WORK}/g.g2o" "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nEDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n")
run(2 "g[.]g2o.*input" "${TOOL}" info g.g2o --plot-graph g.g2o)
run(2 "a[.]png: is named for two outputs" "${TOOL}" info g.g2o --plot-graph a.png --plot-hessian a.png)
file(READ "${WORK}/g.g2o" kept)
if(NOT kept MATCHES "^VERTEX_SE2 0 0 0 0")
  message(FATAL_ERROR "info overwrote its input")
endif()

file(WRITE "${WORK}/g3.g2o" "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\nVERTEX_SE3:QUAT 1 1 0 0 0 0 0 1\n"
  "EDGE_SE3:QUAT 0 1 1 0 0 0 0 0 1 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 1\n")
run(2 "--reject-outliers with --gnc-init robust .the default. places 2D pose graphs"
    "${TOOL}" optimize g3.g2o --reject-outliers)
file(WRITE "${WORK}/zero.g2o" "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\nVERTEX_SE3:QUAT 1 1 0 0 1e-300 0 0 0\n")
run(2 "zero[.]g2o:2: VERTEX_SE3:QUAT: the quaternion .* has norm [0-9.e-]+, not 1"
    "${TOOL}" optimize zero.g2o)

step("final chi2" "${TOOL}" incremental g.g2o -q)
step("default: 1e-12|\\(=1e-12\\)" "${TOOL}" optimize --help)
execute_process(COMMAND "${TOOL}" optimize --help OUTPUT_VARIABLE help)
if(help MATCHES "9999999|0000000[1-9]")
  message(FATAL_ERROR "a default is printed with 17 digits:\n${help}")
endif()

# The auto solver's cost model from GRAPHSLAM_CALIBRATION: a file that cannot be used is an
# error naming it and its line; a usable one is taken (here one in which eigen-ldlt costs
# nothing, so auto names it).
file(WRITE "${WORK}/bad_model.txt" "eigen-ldlt 0 0 x\n")
run(2 "bad_model[.]txt:1: expected NAME" ${CMAKE_COMMAND} -E env GRAPHSLAM_CALIBRATION=bad_model.txt
    "${TOOL}" optimize g.g2o)
file(WRITE "${WORK}/ldlt_model.txt" "# every backend but eigen-ldlt costs a second\n"
  "block-llt-1 1 0 0\nblock-llt-2 1 0 0\nblock-llt-3 1 0 0\nblock-llt-6 1 0 0\n"
  "eigen-ldlt 0 0 0\ncholmod-supernodal 1 0 0\nmetis 1 0 0\n")
run(0 "linear solver auto: eigen-ldlt" ${CMAKE_COMMAND} -E env GRAPHSLAM_CALIBRATION=ldlt_model.txt
    "${TOOL}" optimize g.g2o)
run(0 "linear solver auto: block-llt" "${TOOL}" optimize g.g2o)

# drivebot says which optimizer ran the per-step optimisations, and --optimizer switches it.
foreach(optimizer incremental batch)
  step("optimizer: ${optimizer}" "${TOOL}" drivebot --scenario q1_b --max-steps 60
       --optimizer ${optimizer} --out db_${optimizer})
  file(READ "${WORK}/db_${optimizer}/summary.csv" summary)
  if(NOT summary MATCHES "\noptimizer,${optimizer}\n")
    message(FATAL_ERROR "summary.csv does not name the ${optimizer} optimizer:\n${summary}")
  endif()
endforeach()
run(2 "--optimizer must be" "${TOOL}" drivebot --scenario q1_b --optimizer fast --out db_x)
run(2 "--max-steps must be at least 1" "${TOOL}" drivebot --scenario q1_b --max-steps 0 --out db_0)
