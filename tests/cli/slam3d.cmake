# SPDX-License-Identifier: MIT
# 3D files through the tool: cubicle's indefinite information matrices are one clear error
# by default and are repaired on request.
#   cmake -DTOOL=graphslam -DDATA=datasets-folder -DWORK=scratch-folder -P slam3d.cmake
set(cubicle ${DATA}/cubicle.g2o)
if(NOT EXISTS ${cubicle})
  message("GRAPHSLAM_SKIP: ${cubicle} not found (set GRAPHSLAM_DATA)")
  return()
endif()

include(${CMAKE_CURRENT_LIST_DIR}/steps.cmake)  # run(EXIT REGEX COMMAND...)

run(2 "cubicle.g2o:5753: EDGE_SE3:QUAT: information matrix is not positive definite.*cubicle.g2o: 5021 of 16869 edges have an information matrix that is not positive definite \\(the first 5 are listed above\\); --information nearest-pd or --information isotropic repairs them"
    ${TOOL} optimize ${cubicle})
run(0 "5021 of 16869 information matrices were not positive definite and were repaired \\(isotropic\\).*global 3D \\(chordal\\), 5749 poses.*status: +converged.*chi2: +[0-9.]+ -> 633\\.67"
    ${TOOL} optimize ${cubicle} --information isotropic -q)
run(2 "--information must be refuse, nearest-pd or isotropic, not 'psd'" ${TOOL} optimize ${cubicle} --information psd)
# info takes the same option: it refuses by default and reports on the repaired graph.
run(2 "cubicle.g2o: 5021 of 16869 edges have an information matrix that is not positive definite"
    ${TOOL} info ${cubicle})
run(0 "5021 of 16869 information matrices were not positive definite and were repaired \\(nearest-pd\\).*16869 edges"
    ${TOOL} info ${cubicle} --information nearest-pd)
