# SPDX-License-Identifier: MIT
# The observability check of graphslam optimize and info (tests/data/observability): each
# undetermined case named with its reason and its edges' lines; optimize refuses such a graph
# before iterating (exit 2, no output), whatever the algorithm; --drop-unobservable removes
# the vertices and converges; an unanchored component is information only; a joint
# degeneracy found by the factorisation names the vertex and its edge's line, for every
# algorithm (damped ones by a factorisation of H at the result).
#   cmake -DTOOL=graphslam -DPLUGIN=libgraphslam_test_plugin.so -DDATA=tests/data/observability
#         -DWORK=dir -P observability.cmake
include(${CMAKE_CURRENT_LIST_DIR}/steps.cmake)

function(expect_no_output path)
  if(EXISTS "${path}")
    message(FATAL_ERROR "${path} was written")
  endif()
endfunction()

# A vertex without edges.
run(2 "no_edges.g2o: 1 vertex is not determined by the edges:\n  vertex 9 [(]VERTEX_XY[)]: no edges\nnot optimising: --drop-unobservable removes" "${TOOL}"
       optimize "${DATA}/no_edges.g2o" -o "${WORK}/no_edges.g2o" --stats "${WORK}/no_edges.csv")
expect_no_output("${WORK}/no_edges.g2o")
expect_no_output("${WORK}/no_edges.csv")
run(0 "observability: 1 vertex is not determined by the edges:\n  vertex 9 [(]VERTEX_XY[)]: no edges" "${TOOL}"
       info "${DATA}/no_edges.g2o")

# Landmarks seen by one range, by two bearings from one pose, by parallel bearings; 13 is
# determined (two bearings from different directions).
set(range "vertex 10 [(]VERTEX_XY[)]: one range-only edge [(]from vertex 1[)]: it can move on a circle around vertex 1 [[]edge on line 15[]]")
set(one_pose "vertex 11 [(]VERTEX_XY[)]: seen from one vertex [(]1[)] by bearing only: it can slide along the line of sight [[]edges on lines 16, 17[]]")
set(parallel "vertex 12 [(]VERTEX_XY[)]: bearing-only edges all along one line [(]parallel bearings[)] from vertices 0 and 2: it can slide along that line [[]edges on lines 18, 19[]]")
set(list "3 vertices are not determined by the edges:\n  ${range}\n  ${one_pose}\n  ${parallel}\n")
foreach(algorithm auto gn lm dogleg)
  run(2 "landmarks.g2o: ${list}not optimising" "${TOOL}"
         optimize "${DATA}/landmarks.g2o" --plugin "${PLUGIN}" --algorithm ${algorithm}
         -o "${WORK}/landmarks_${algorithm}.g2o")
  expect_no_output("${WORK}/landmarks_${algorithm}.g2o")
endforeach()
run(0 "observability: ${list}" "${TOOL}" info "${DATA}/landmarks.g2o" --plugin "${PLUGIN}")

# --drop-unobservable: says how many and which, then optimises the rest.
run(0 "${list}dropped 3 vertices [(]10, 11, 12[)] and 5 edges [(]--drop-unobservable[)].*status: +converged.*wrote" "${TOOL}"
       optimize "${DATA}/landmarks.g2o" --plugin "${PLUGIN}" --drop-unobservable --algorithm lm
       -o "${WORK}/dropped.g2o")
file(STRINGS "${WORK}/dropped.g2o" written)
list(LENGTH written n)
if(NOT n EQUAL 9)  # poses 0-2, landmark 13, FIX 0, two odometry and two bearing edges
  message(FATAL_ERROR "dropped.g2o has ${n} lines, expected 9:\n${written}")
endif()
run(0 "status: +converged" "${TOOL}" optimize "${DATA}/no_edges.g2o" --drop-unobservable)

# Components without an anchor: information, and the optimizer anchors each.
run(0 "information: 2 components have no anchor [(]no fixed vertex, no prior[)]; the optimizer fixes one vertex of each [(]its lowest id of the largest dimension[)] for the run: 0 [(]2 vertices[)], 5 [(]2 vertices[)].*status: +converged.*gauge: +fixed vertex 0 5" "${TOOL}"
       optimize "${DATA}/unanchored.g2o")
run(0 "observability: every non-fixed vertex is determined by its edges\ninformation: 2 components have no anchor" "${TOOL}"
       info "${DATA}/unanchored.g2o")

# Every vertex's own block is determined, the system is not: the factorisation fails and
# names the vertex, its neighbours and its edge's line.
run(1 "numerical failure: .*[(]at vertex 2[)]; its edge joins it to vertex 1; its single edge determines it when the other vertices are held fixed: it is undetermined together with its neighbours.*vertex 2: its edge is on line 9 of [^\n]*joint_degeneracy.g2o" "${TOOL}"
       optimize "${DATA}/joint_degeneracy.g2o" --plugin "${PLUGIN}" --algorithm gn
       -o "${WORK}/joint.g2o")
expect_no_output("${WORK}/joint.g2o")
# Damped algorithms step past the singular H; at the result the tool factorises it once and
# fails the same way instead of reporting "converged".
foreach(algorithm lm dogleg auto)
  run(1 "converged by [a-z -]+, but H is singular at the result [(]the damping hid it[)]: H is not positive definite at vertex 2.*vertex 2: edges on line 9.*not writing outputs"
      "${TOOL}" optimize "${DATA}/joint_degeneracy.g2o" --plugin "${PLUGIN}" --algorithm ${algorithm}
      -o "${WORK}/joint_${algorithm}.g2o")
  expect_no_output("${WORK}/joint_${algorithm}.g2o")
endforeach()
# Bearing-only landmarks with ids below the poses' (as g2o_simulator2d writes them): the one
# seen once is named before iterating; without it the graph converges with a pose, not
# landmark 1, fixed as the gauge (fixing a landmark would leave the rotation about it free).
run(2 "vertex 8 [(]VERTEX_XY[)]: seen from one vertex [(]100[)] by bearing only: it can slide along the line of sight [[]edge on line 206[]].*not optimising"
    "${TOOL}" optimize "${DATA}/bearing_landmarks_first.g2o" -o "${WORK}/bearing.g2o")
expect_no_output("${WORK}/bearing.g2o")
run(0 "dropped 1 vertex [(]8[)] and 1 edge.*fixes one vertex of each [(]its lowest id of the largest dimension[)] for the run: 100 [(]39 vertices[)].*status: +converged.*gauge: +fixed vertex 100\n.*wrote"
    "${TOOL}" optimize "${DATA}/bearing_landmarks_first.g2o" --drop-unobservable -o "${WORK}/bearing.g2o")
