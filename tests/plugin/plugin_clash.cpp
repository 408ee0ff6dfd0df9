// SPDX-License-Identifier: MIT
// A plugin registering a tag the program has already (VERTEX_SE2, with a type of its own):
// refused, naming both registrations.
#include "graphslam/core/base_vertex.h"
#include "graphslam/core/plugin.h"

namespace {
class OtherPose final : public graphslam::BaseVertex<3, Eigen::Vector3d> {
 public:
  [[nodiscard]] Eigen::Vector3d plus(const Eigen::Vector3d& x,
                                     const TangentVector& delta) const override {
    return x + delta;
  }
};
}  // namespace

GRAPHSLAM_PLUGIN_ENTRY(host) { host.types->registerVertex<OtherPose>("VERTEX_SE2"); }
