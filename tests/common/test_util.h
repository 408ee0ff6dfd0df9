// SPDX-License-Identifier: MIT
// Shared helpers of the test suites.
#pragma once

#include <Eigen/Core>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "graphslam/core/edge.h"
#include "graphslam/core/graph.h"
#include "graphslam/core/jacobian_check.h"

namespace graphslam::test {

/// Directory of the public datasets: $GRAPHSLAM_DATA, else the configured default.
inline std::string dataDir() {
  if (const char* env = std::getenv("GRAPHSLAM_DATA"); env && *env) return env;
#ifdef GRAPHSLAM_DEFAULT_DATA_DIR
  return GRAPHSLAM_DEFAULT_DATA_DIR;
#else
  return "../shared/datasets";
#endif
}

inline bool fileExists(const std::string& path) { return std::ifstream(path).good(); }

// The Jacobian checks every edge type is tested with are the library's own
// (graphslam/core/jacobian_check.h), which plugin authors use too.
using graphslam::checkJacobians;
using graphslam::numericJacobian;

/// Checks that `statement` throws `Exception` whose message contains `fragment`.
#define EXPECT_THROW_MSG(statement, Exception, fragment)                                    \
  do {                                                                                      \
    try {                                                                                   \
      statement;                                                                            \
      ADD_FAILURE() << "no " #Exception " thrown by " #statement;                           \
    } catch (const Exception& e) {                                                          \
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << "got: " << e.what(); \
    }                                                                                       \
  } while (false)

}  // namespace graphslam::test
