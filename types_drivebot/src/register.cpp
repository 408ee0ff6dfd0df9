// SPDX-License-Identifier: MIT
#include "graphslam/types_drivebot/register.h"

#include "graphslam/types_drivebot/edge_compass.h"
#include "graphslam/types_drivebot/edge_gps.h"
#include "graphslam/types_drivebot/edge_landmark_range_bearing.h"
#include "graphslam/types_drivebot/edge_vehicle_kinematics.h"
#include "graphslam/types_drivebot/edge_vehicle_prior.h"
#include "graphslam/types_drivebot/vertex_landmark.h"
#include "graphslam/types_drivebot/vertex_vehicle.h"

namespace graphslam::types_drivebot {

void registerTypes(TypeRegistry& registry) {
  registry.registerVertex<VertexVehicle>("VERTEX_VEHICLE");
  registry.registerVertex<VertexLandmark>("VERTEX_LANDMARK");
  registry.registerEdge<EdgeVehicleKinematics>("EDGE_VEHICLE_KINEMATICS");
  registry.registerEdge<EdgeGps>("EDGE_GPS");
  registry.registerEdge<EdgeCompass>("EDGE_COMPASS");
  registry.registerEdge<EdgeLandmarkRangeBearing>("EDGE_LANDMARK_RANGE_BEARING");
  registry.registerEdge<EdgeVehiclePrior>("EDGE_VEHICLE_PRIOR");
}

}  // namespace graphslam::types_drivebot
