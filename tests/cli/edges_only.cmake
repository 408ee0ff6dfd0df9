# SPDX-License-Identifier: MIT
# Files without vertex lines: every command that reads a graph creates the vertices from the
# edges and says so. MODE small: tests/data/edges_only.g2o through optimize, info, convert
# and deadreckon. MODE datasets: every kitti_* and *_sesync file of the datasets folder
# ($GRAPHSLAM_DATA, else DATA) is optimised with the tool's defaults and reaches its final
# chi2 (kitti_00: the best known 98.322012), and so does tinygrid3d without its vertex lines;
# skipped ("GRAPHSLAM_SKIP:") without the folder.
#   cmake -DTOOL=graphslam -DMODE=small|datasets -DDATA=dir -DWORK=dir -P edges_only.cmake
include(${CMAKE_CURRENT_LIST_DIR}/steps.cmake)

if(MODE STREQUAL "small")
  set(f "${DATA}/edges_only.g2o")
  set(created "created 4 vertices from edges [(]the file has no vertex lines")
  step("${created}.*initialisation: global, 3 poses.*status: +converged.*chi2: +[0-9.e-]+ -> [0-9.]+e-[0-9]+.*wrote"
       "${TOOL}" optimize "${f}" -o "${WORK}/square.g2o")
  file(STRINGS "${WORK}/square.g2o" vertices REGEX "^VERTEX_SE2")
  list(LENGTH vertices n)
  if(NOT n EQUAL 4)
    message(FATAL_ERROR "square.g2o has ${n} VERTEX_SE2 lines, expected 4")
  endif()
  step("${created}.*VERTEX_SE2 +4\n.*every non-fixed vertex is determined" "${TOOL}" info "${f}")
  step("${created}.*initialisation: global.*wrote .*square.tum: 4 poses"
       "${TOOL}" convert "${f}" "${WORK}/square.tum")
  # Dead reckoning starts at the identity: (0, 0, 0), (1, 0, 90), (1, 1, 180), (0, 1, -90).
  step("${created}.*4 poses; last [(]pose 3[)]: x 0.000000  y 1.000000  theta -1.570796 rad"
       "${TOOL}" deadreckon "${f}" -o "${WORK}/square_dr.tum")
  return()
endif()

if(DEFINED ENV{GRAPHSLAM_DATA} AND NOT "$ENV{GRAPHSLAM_DATA}" STREQUAL "")
  set(DATA "$ENV{GRAPHSLAM_DATA}")
endif()
if(NOT EXISTS "${DATA}/kitti_00.g2o")
  message("datasets not found in ${DATA} (set GRAPHSLAM_DATA)")
  message("GRAPHSLAM_SKIP: no datasets folder")
  return()
endif()
# file:vertices created:the final chi2's leading digits (1e-6 relative or better).
set(cases
    "kitti_00:4541:98[.]32201"
    "kitti_02:4661:78[.]76432"
    "kitti_05:2761:157[.]1043"
    "kitti_06:1101:25[.]94708"
    "kitti_07:1101:12[.]66103"
    "kitti_08:4071:[0-9.]+e-[12][0-9]"  # a chain without loop closures: chi2 0
    "kitti_09:1591:34[.]38282"
    "csail_sesync:1045:40[.]55512"
    "manhattan_sesync:3500:3549[.]036")
foreach(c IN LISTS cases)
  string(REPLACE ":" ";" fields "${c}")
  list(GET fields 0 name)
  list(GET fields 1 n)
  list(GET fields 2 chi2)
  step("created ${n} vertices from edges.*status: +converged.*chi2: +[0-9.e+-]+ -> ${chi2}.*time: +[0-9.e-]+ s"
       "${TOOL}" optimize "${DATA}/${name}.g2o" -q)
endforeach()
# 3D: tinygrid3d without its vertex lines creates VERTEX_SE3:QUAT vertices, which the chordal
# 3D initialisation places, and reaches the file's own optimum (its best known chi2).
file(STRINGS "${DATA}/tinygrid3d.g2o" edges REGEX "^EDGE")
list(JOIN edges "\n" text)
file(WRITE "${WORK}/tinygrid3d_edges.g2o" "${text}\n")
step("created 9 vertices from edges.*global 3D.*status: +converged.*chi2: +[0-9.e+-]+ -> 6[.]727881"
     "${TOOL}" optimize "${WORK}/tinygrid3d_edges.g2o" -q)
