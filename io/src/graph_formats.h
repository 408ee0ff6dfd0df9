// SPDX-License-Identifier: MIT
// The io module's own formats, registered by registerFormats (register.h). Private.
#pragma once

#include "graphslam/io/format_registry.h"

namespace graphslam::io {

/// .g2o, TORO, iSAM, the CMU homework's .npz, the relative-pose matrix.
void registerGraphFormats(FormatRegistry& formats);
/// TUM and KITTI trajectories.
void registerTrajectoryFormats(FormatRegistry& formats);

}  // namespace graphslam::io
