# SPDX-License-Identifier: MIT
# The replay of a loaded graph through the IncrementalOptimizer (replay.h, graph_copy.h),
# included by incremental/CMakeLists.txt.
target_sources(graphslam_incremental PRIVATE
  ${CMAKE_CURRENT_SOURCE_DIR}/src/replay.cpp
  ${CMAKE_CURRENT_SOURCE_DIR}/src/batch_check.cpp
  ${CMAKE_CURRENT_SOURCE_DIR}/src/graph_copy.cpp)
