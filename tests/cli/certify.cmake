# SPDX-License-Identifier: MIT
# graphslam certify end to end: a simulated 2D and 3D pose graph certified and written;
# landmarks, a disconnected graph and bad options refused with the reason, nothing written;
# optimize --certify names the objective it certified and refines chi2 from it.
#   cmake -DTOOL=graphslam -DDATA=dir -DWORK=dir -P certify.cmake
include(${CMAKE_CURRENT_LIST_DIR}/steps.cmake)

step("wrote" "${TOOL}" simulate -o m.g2o --poses 300 --seed 3)
step("certified globally optimal\n  F[(]x[)] [0-9.]+ [(]SE-Sync's objective, 2D, 300 poses.*dual bound.*relative suboptimality bound.*lambda_min[(]S[)].*residual.*rank 5; time.*wrote c.g2o"
     "${TOOL}" certify m.g2o -o c.g2o)
file(STRINGS "${WORK}/c.g2o" poses REGEX "^VERTEX_SE2")
list(LENGTH poses n)
if(NOT n EQUAL 300)
  message(FATAL_ERROR "c.g2o has ${n} VERTEX_SE2 lines, expected 300")
endif()
step("wrote" "${TOOL}" simulate -o s.g2o --poses 200 --3d sphere)
step("certified globally optimal\n.*3D, 200 poses" "${TOOL}" certify s.g2o --start estimates)

# Refusals: exit 2, the reason named, no output.
step("wrote" "${TOOL}" simulate -o l.g2o --poses 100 --landmarks 20)
run(2 "l.g2o: vertex [0-9]+ is a VERTEX_XY; certify supports pose graphs only"
    "${TOOL}" certify l.g2o -o out.g2o)
file(WRITE "${WORK}/two.g2o"
     "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nVERTEX_SE2 2 5 0 0\nVERTEX_SE2 3 6 0 0\n"
     "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\nEDGE_SE2 2 3 1 0 0 1 0 0 1 0 1\n")
run(2 "the graph is disconnected [(]2 components; vertex 2 is not connected to vertex 0[)]"
    "${TOOL}" certify two.g2o -o out.g2o)
run(2 "--initial-rank must be at least 2" "${TOOL}" certify m.g2o --initial-rank 1)
run(2 "start" "${TOOL}" certify m.g2o --start nowhere)
if(EXISTS "${WORK}/out.g2o")
  message(FATAL_ERROR "a refused run wrote out.g2o")
endif()

# optimize --certify: SE-Sync's objective certified, then the file's chi2 refined.
step("certify: SE-Sync's objective [(]chordal rotation and translation terms with isotropic weights from the edges' information[)], not the file's chi2:\ncertified globally optimal.*refining the optimizer's own objective.*status: +converged"
     "${TOOL}" optimize m.g2o --certify)
