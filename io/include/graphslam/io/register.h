// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/io/format_registry.h"

namespace graphslam::io {

/// Registers the io module's formats: graphs (g2o, toro, isam, npz, matrix) and
/// trajectories (tum, kitti). Other modules register theirs (drivebot::registerFormats).
void registerFormats(FormatRegistry& formats);

}  // namespace graphslam::io
