# SPDX-License-Identifier: MIT
# The CMU 16-833 HW3 files through the tool (SEEDS.md section 1): the homework's 10
# Gauss-Newton iterations on 2d_nonlinear.npz (chi2 as SciPy computes it, errors against
# the ground truth, the plot), the .g2o round trip of the point-robot types, and the linear
# files. Skipped when the data folder is absent: the
# test matches the printed "GRAPHSLAM_SKIP:" (SKIP_REGULAR_EXPRESSION; CMake 3.25 has no
# cmake_language(EXIT)).
#   cmake -DTOOL=... -DDATA=... -DWORK=... -P coursework.cmake
set(seeds "${DATA}/seeds")
if(NOT EXISTS "${seeds}/2d_nonlinear.npz")
  message("homework data not found in ${seeds} (set GRAPHSLAM_DATA)")
  message("GRAPHSLAM_SKIP: no data folder")
  return()
endif()
include(${CMAKE_CURRENT_LIST_DIR}/steps.cmake)
step("observation model bearing-range.*initialisation: none.*chi2: +8623.3224[0-9]* -> 1555.1896[0-9]*\niterations: +10.*poses +100 +rmse 0.057883 .* -> +rmse 0.015333 .*landmarks +15 +rmse 0.191390 .* -> +rmse 0.019019 .*wrote nl.g2o.*wrote nl.png"
     ${TOOL} optimize ${seeds}/2d_nonlinear.npz --algorithm gn -i 10 --function-tolerance 0 --step-tolerance 0 -o nl.g2o --plot nl.png)
if(NOT EXISTS "${WORK}/nl.png")
  message(FATAL_ERROR "nl.png was not written")
endif()
# The written graph uses EDGE_PRIOR_XY, EDGE_POINTXY and EDGE_XY_BEARING_RANGE; reading it
# back gives the same chi2.
step("EDGE_POINTXY +99\n +EDGE_PRIOR_XY +1\n +EDGE_XY_BEARING_RANGE +766" ${TOOL} info nl.g2o)
step("chi2: +1555.1896[0-9]* -> 1555.1896" ${TOOL} optimize nl.g2o --init none --algorithm gn -i 1)
step("observation model linear.*chi2: +[0-9.e+]+ -> 7802.57[0-9]*.*poses +200 +rmse 1.400496 .* -> +rmse 0.045097 .*landmarks +200 +rmse 1.414144 .* -> +rmse 0.043372"
     ${TOOL} optimize ${seeds}/2d_linear_loop.npz --algorithm gn)
step("1100 vertices, 53566 edges.*EDGE_POINTXY +53565\n +EDGE_PRIOR_XY +1" ${TOOL} info ${seeds}/2d_linear.npz)
# convert writes the homework's graph with its initial guess: optimising that .g2o from its
# estimates is the same run as optimising the .npz.
step("read .*2d_nonlinear.npz: CMU 16-833 homework file, bearing-range observations: 100 poses.*wrote nl0.g2o"
     ${TOOL} convert ${seeds}/2d_nonlinear.npz nl0.g2o)
step("chi2: +8623.3224[0-9]* -> 1555.1896[0-9]*\niterations: +10"
     ${TOOL} optimize nl0.g2o --init none --algorithm gn -i 10 --function-tolerance 0 --step-tolerance 0)
# Sparsity pictures: block-llt (the default solver's factorisation) exports its factor, and
# each picture's title gives the solver table's nnz(factor).
execute_process(COMMAND /usr/bin/python3 -c "import matplotlib" RESULT_VARIABLE no_mpl OUTPUT_QUIET ERROR_QUIET)
if(NOT no_mpl)
  step("block-llt +amd +H .* 42880 .*wrote 3 sparsity pictures and the estimate into spy"
       ${TOOL} solvers ${seeds}/2d_linear_loop.npz --solvers block-llt:amd --repeats 1 --plot spy)
  file(STRINGS ${WORK}/spy/data/2d_linear_loop_block-llt_amd.csv head LIMIT_COUNT 1)
  if(NOT head MATCHES "^800,800,42880,")
    message(FATAL_ERROR "block-llt's factor picture: ${head}, expected 42880 non-zeros as in the table")
  endif()
  if(NOT EXISTS "${WORK}/spy/2d_linear_loop_block-llt_amd.png")
    message(FATAL_ERROR "no picture of block-llt's factor")
  endif()
endif()
