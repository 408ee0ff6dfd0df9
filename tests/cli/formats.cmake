# SPDX-License-Identifier: MIT
# TORO and iSAM files through the tool. MODE small: tests/data/formats through convert and
# optimize (recognised by their tags), and bad lines named by FILE:LINE. MODE datasets: the
# TORO and iSAM originals in the datasets folder's sources/ ($GRAPHSLAM_DATA, else DATA)
# convert to the .g2o files the folder holds (MANIFEST.md) and reach the same final chi2;
# skipped ("GRAPHSLAM_SKIP:") without the folder.
#   cmake -DTOOL=graphslam -DMODE=small|datasets -DDATA=dir -DWORK=dir -P formats.cmake
include(${CMAKE_CURRENT_LIST_DIR}/steps.cmake)

if(MODE STREQUAL "small")
  # TORO 2D: information xx xy yy tt xt yt (100 0 100 400 0 0) written in g2o's order.
  step("TORO graph, read as .g2o: 4 vertex lines, 4 edge lines.*wrote .*square.g2o: 4 vertices, 4 edges"
       "${TOOL}" convert "${DATA}/square.graph" "${WORK}/square.g2o")
  file(STRINGS "${WORK}/square.g2o" edges REGEX "^EDGE_SE2 ")
  list(GET edges 0 first)
  if(NOT first STREQUAL "EDGE_SE2 0 1 1 0 1.5707963267948966 100 0 0 100 0 400")
    message(FATAL_ERROR "unexpected first edge: ${first}")
  endif()
  step("TORO graph.*status: +converged" "${TOOL}" optimize "${DATA}/square.graph")
  # TORO 3D: VERTEX3 / EDGE3 become VERTEX_SE3:QUAT / EDGE_SE3:QUAT.
  step("TORO graph, read as .g2o: 3 vertex lines, 3 edge lines.*status: +converged"
       "${TOOL}" optimize "${DATA}/pose3.graph" -o "${WORK}/pose3.g2o")
  file(STRINGS "${WORK}/pose3.g2o" vertices REGEX "^VERTEX_SE3:QUAT ")
  list(LENGTH vertices n)
  if(NOT n EQUAL 3)
    message(FATAL_ERROR "pose3.g2o has ${n} VERTEX_SE3:QUAT lines, expected 3")
  endif()
  # iSAM 2D: no vertex lines; landmark ids collide with pose ids and move past them.
  step("iSAM graph, read as .g2o: 0 vertex lines, 7 edge lines.*landmark l is vertex l [+] 3.*created 5 vertices from edges.*status: +converged"
       "${TOOL}" optimize "${DATA}/landmarks_isam.txt" -o "${WORK}/landmarks.g2o")
  file(STRINGS "${WORK}/landmarks.g2o" landmarks REGEX "^VERTEX_XY ")
  if(NOT landmarks MATCHES "^VERTEX_XY 3 1 1;VERTEX_XY 4 2 -1$")
    message(FATAL_ERROR "unexpected landmarks: ${landmarks}")
  endif()
  step("created 5 vertices from edges.*initialisation: global.*wrote .*landmarks_converted.g2o: 5 vertices, 7 edges"
       "${TOOL}" convert "${DATA}/landmarks_isam.txt" "${WORK}/landmarks_converted.g2o")
  # Bad input: FILE:LINE and the reason, exit 2, nothing written.
  run(2 "bad_isam.txt:2: ODOMETRY: value 5 'zero' is not a number"
      "${TOOL}" convert "${DATA}/bad_isam.txt" "${WORK}/bad.g2o")
  if(EXISTS "${WORK}/bad.g2o")
    message(FATAL_ERROR "bad.g2o written although the input is bad")
  endif()
  step("wrote .*x.tum: 4 poses" "${TOOL}" convert "${DATA}/square.graph" "${WORK}/x.tum")
  run(2 "--from must be auto, g2o, toro, isam, npz, matrix, not 'x'"
      "${TOOL}" convert "${DATA}/square.graph" "${WORK}/x.g2o" --from x)
  return()
endif()

if(DEFINED ENV{GRAPHSLAM_DATA} AND NOT "$ENV{GRAPHSLAM_DATA}" STREQUAL "")
  set(DATA "$ENV{GRAPHSLAM_DATA}")
endif()
if(NOT EXISTS "${DATA}/sources/nanopgo_CSAIL_P_toro.graph")
  message("dataset sources not found in ${DATA}/sources (set GRAPHSLAM_DATA)")
  message("GRAPHSLAM_SKIP: no datasets folder")
  return()
endif()
# source:the .g2o file converted from it:its final chi2's leading digits (both files).
set(cases
    "nanopgo_CSAIL_P_toro.graph:csail:38[.]956285"
    "nanopgo_FR079_P_toro.graph:fr079:37[.]599115"
    "nanopgo_FRH_P_toro.graph:frh:0[.]000193136"
    "isam_victoriaPark.txt:victoria_park:6184[.]1206"
    "isam_cityTrees10000.txt:citytrees10000:8668[.]9280")
foreach(c IN LISTS cases)
  string(REPLACE ":" ";" fields "${c}")
  list(GET fields 0 source)
  list(GET fields 1 name)
  list(GET fields 2 chi2)
  step("wrote .*${name}.g2o" "${TOOL}" convert "${DATA}/sources/${source}" "${WORK}/${name}.g2o")
  step("status: +converged.*chi2: +[0-9.e+-]+ -> ${chi2}" "${TOOL}" optimize "${WORK}/${name}.g2o" -q)
  step("status: +converged.*chi2: +[0-9.e+-]+ -> ${chi2}" "${TOOL}" optimize "${DATA}/${name}.g2o" -q)
endforeach()
