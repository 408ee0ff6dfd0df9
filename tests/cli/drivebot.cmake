# SPDX-License-Identifier: MIT
# graphslam drivebot end to end. MODE=short: a few short runs (files written, the final
# graph reloads, plots drawn when matplotlib is there, the q3_a failure leaves nothing
# behind). MODE=experiments: every coursework experiment at full length. MODE=every-step:
# q2_c optimised after every step (long).
#   cmake -DTOOL=... -DWORK=... -DMODE=short|experiments|every-step -P drivebot.cmake
include(${CMAKE_CURRENT_LIST_DIR}/steps.cmake)
function(expect_files dir)
  foreach(f ${ARGN})
    if(NOT EXISTS "${WORK}/${dir}/${f}")
      message(FATAL_ERROR "${dir}/${f} was not written")
    endif()
  endforeach()
endfunction()

if(MODE STREQUAL "short")
  run(0 "graph: +400 vehicle vertices, 5 landmark vertices.*observations: .*per landmark.*wrote"
      ${TOOL} drivebot --experiment q2_b --max-steps 400 --out q2b)
  expect_files(q2b steps.csv landmarks.csv scenario.csv graph_stats.csv final.g2o)
  file(STRINGS ${WORK}/q2b/steps.csv rows)
  list(LENGTH rows n)
  if(NOT n EQUAL 401)
    message(FATAL_ERROR "steps.csv has ${n} lines, expected 401 (header + 400 steps)")
  endif()
  run(0 "405 vertices, 787 edges.*VERTEX_VEHICLE +400.*fixed vertices: 1: 0" ${TOOL} info q2b/final.g2o)
  run(0 "status: +converged" ${TOOL} optimize q2b/final.g2o --init none)
  # Same seed, same graph (steps.csv also holds wall times); another seed, another graph.
  run(0 "wrote" ${TOOL} drivebot --experiment q2_b --max-steps 400 --out q2b_again -q)
  file(READ ${WORK}/q2b/final.g2o a)
  file(READ ${WORK}/q2b_again/final.g2o b)
  if(NOT a STREQUAL b)
    message(FATAL_ERROR "the same seed gave a different final.g2o")
  endif()
  run(0 "wrote" ${TOOL} drivebot --experiment q2_b --max-steps 400 --seed 9 --out q2b_seed9 -q)
  file(READ ${WORK}/q2b_seed9/final.g2o c)
  if(a STREQUAL c)
    message(FATAL_ERROR "seeds 1 and 9 gave the same final.g2o")
  endif()
  # q3_a with all prediction edges removed: a diagnosis naming vertices, exit 1, no files.
  run(1 "optimisation at step 499 .*failed: under-determined.*no fixed vertex or prior connects to [0-9]+ vehicle vertices 1.*landmarks.*all prediction edges were removed.*first vehicle vertex 0.*no results written"
      ${TOOL} drivebot --experiment q3_a_all --max-steps 600 --out q3a_all)
  if(EXISTS "${WORK}/q3a_all/steps.csv" OR EXISTS "${WORK}/q3a_all/final.g2o")
    message(FATAL_ERROR "the failed run wrote results")
  endif()
  # The coursework's pruning halves each landmark's observation edges at every optimisation.
  run(0 "prune: coursework.*observations: +([0-9]+) received, ([0-9]+) in the graph"
      ${TOOL} drivebot --experiment q3_b_coursework --max-steps 1000 --out q3b_coursework -q)
  file(STRINGS ${WORK}/q3b_coursework/graph_stats.csv kept REGEX "^observation_edges,")
  file(STRINGS ${WORK}/q3b_coursework/graph_stats.csv received REGEX "^observations_received,")
  string(REGEX REPLACE ".*," "" kept "${kept}")
  string(REGEX REPLACE ".*," "" received "${received}")
  math(EXPR quarter "${received} / 4")
  if(NOT kept LESS quarter)  # optimised at steps 500, 1000 and at the end: under a quarter
    message(FATAL_ERROR "q3_b_coursework kept ${kept} of ${received} observations")
  endif()
  # Timing: thread CPU time with the wall time beside it, the quarters split by step.
  run(0 "optimisation: +201 runs, [0-9.]+ s CPU \\([0-9.]+ s wall\\) in total; median per optimisation [0-9.]+ ms CPU \\([0-9.]+ ms wall\\) in the first quarter of the steps"
      ${TOOL} drivebot --experiment q1_e_i --max-steps 200 --out q1e_i)
  file(STRINGS ${WORK}/q1e_i/steps.csv header LIMIT_COUNT 1)
  if(NOT header MATCHES "optimization_time,optimization_cpu_time,.*,observations,gps,compass$")
    message(FATAL_ERROR "steps.csv header: ${header}")
  endif()
  run(0 "prediction edges removed: keep-first.*graph: .* \\(1 prediction"
      ${TOOL} drivebot --experiment q3_a_keep_first --max-steps 600 --out q3a_keep_first)
  # Options override the preset; bad options are usage errors.
  run(0 "sensors odometry, gps, compass, optimise every 7 steps.*GPS.*compass"
      ${TOOL} drivebot --scenario q1_e --sensors gps,compass --optimize-every 7 --max-steps 100 --out q1e)
  run(2 "--prune must be none, every-second, coursework, staggered or keyframe, not .often." ${TOOL} drivebot --scenario q1_b --prune often --out x)
  run(2 "scenario 'q9' is neither built in" ${TOOL} drivebot --scenario q9 --out x)
  run(2 "needs --out" ${TOOL} drivebot --experiment q1_b)
  run(2 "unknown experiment" ${TOOL} drivebot --experiment q7 --out x)
  run(0 "q2_d +laser SLAM without noise.*q3_b_coursework +q3_a pruning as the coursework did" ${TOOL} drivebot --list-experiments)
  # Plots, when matplotlib is available.
  execute_process(COMMAND /usr/bin/python3 -c "import matplotlib" RESULT_VARIABLE no_mpl OUTPUT_QUIET ERROR_QUIET)
  if(no_mpl)
    message("matplotlib not importable by /usr/bin/python3: plots not checked")
  else()
    # q2_d optimises once during the run (at the closure): one point is no series, not drawn.
    run(0 "loop closure: +at step 12[0-9][0-9].*chi2.png not drawn: .*once during the run, at step 12[0-9][0-9].*plots:"
        ${TOOL} drivebot --experiment q2_d --out q2d --plot -q)
    expect_files(q2d errors.png covariance.png map.png loop_closure.png
                 loop_closure.csv loop_closure_vehicle.csv loop_closure_vehicle.png)
    if(EXISTS "${WORK}/q2d/chi2.png" OR EXISTS "${WORK}/q2d/optimization_time.png")
      message(FATAL_ERROR "q2_d drew a chi2 or timing plot of one point")
    endif()
    file(STRINGS ${WORK}/q2d/loop_closure.csv lc_header LIMIT_COUNT 1)
    file(STRINGS ${WORK}/q2d/loop_closure.csv lc_after REGEX "^after,")
    if(NOT lc_header MATCHES "vehicle_cov_xx,vehicle_cov_xy,vehicle_cov_yy" OR lc_after MATCHES "^after,[0-9]+,[0-9.]+,nan")
      message(FATAL_ERROR "loop_closure.csv: no vehicle covariance or a NaN chi2: ${lc_header}")
    endif()
    # A run that optimises only at its end has no chi2 or timing series: said, not drawn.
    run(0 "chi2.png not drawn: the run optimised only after its last step.*optimization_time.png not drawn"
        ${TOOL} drivebot --experiment q1_b --max-steps 300 --out q1b --plot -q)
    if(EXISTS "${WORK}/q1b/chi2.png" OR EXISTS "${WORK}/q1b/optimization_time.png")
      message(FATAL_ERROR "q1_b drew an empty chi2 or timing plot")
    endif()
  endif()
elseif(MODE STREQUAL "experiments")
  foreach(e q1_b q1_c_bug q1_c q1_d q1_e_i q1_e_ii q2_b q2_c q2_d q3_a q3_a_keep_first
            q3_b_coursework q3_b_every_second q3_b_staggered q3_b_keyframe)
    run(0 "final: +converged.*wrote" ${TOOL} drivebot --experiment ${e} --out ${e} -q)
  endforeach()
  run(1 "all prediction edges were removed" ${TOOL} drivebot --experiment q3_a_all --out q3_a_all -q)
elseif(MODE STREQUAL "every-step")
  # q2_c optimised after each of its 5273 steps (incremental updates, then the batch
  # end-of-run optimisation from their estimate: one or two Gauss-Newton iterations, as
  # the updates stop within the relinearisation threshold of the optimum), the same final
  # chi2 as optimising once at the end (the value itself depends on the compiler's
  # rounding of the simulation: g++ 6326.25).
  execute_process(COMMAND ${TOOL} drivebot --experiment q2_c --out once -q
                  WORKING_DIRECTORY "${WORK}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  string(REGEX MATCH "final: +converged, chi2 ([0-9]+[.][0-9]+)" final "${out}${err}")
  if(NOT rc EQUAL 0 OR NOT final)
    message(FATAL_ERROR "q2_c optimised once did not converge (exit ${rc}):\n${out}${err}")
  endif()
  string(REPLACE "." "[.]" chi2 "${CMAKE_MATCH_1}")
  run(0 "optimisation: +5274 runs.*final: +converged, chi2 ${chi2}, [12] iterations"
      ${TOOL} drivebot --experiment q2_c_every_step --out every_step -q)
else()
  message(FATAL_ERROR "MODE must be short, experiments or every-step")
endif()
