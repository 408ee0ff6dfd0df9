// SPDX-License-Identifier: MIT
// graphslam certify, and optimize --certify.
#pragma once

#include <string>
#include <vector>

#include "cli_common.h"
#include "graphslam/certify/certify.h"

namespace graphslam::apps {

int cmdCertify(const std::vector<std::string>& args);

/// Refuses a graph certify cannot take, naming the vertex's or edge's tag and the file.
void checkCertifiable(const Graph& graph, const TypeRegistry& types, const std::string& input);

/// optimize --certify: certifies SE-Sync's objective on `graph` (writing the rounded optimum
/// into it) and prints what was certified; returns whether it was.
bool certifyBeforeOptimize(Graph& graph, const TypeRegistry& types, const std::string& input);

}  // namespace graphslam::apps
