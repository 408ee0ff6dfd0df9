// SPDX-License-Identifier: MIT
// Time-stamped sensor events of the DriveBot world (simulated or real) and the ordered
// queue one simulation step delivers them in.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace graphslam::drivebot {

enum class EventType {
  kInitialCondition,  ///< value: initial state (x, y, psi); covariance 3x3
  kOdometry,          ///< value: u = (speed, lateral speed, yaw rate); covariance 3x3
  kGps,               ///< value: GPS antenna position (x, y) in the world; covariance 2x2
  kCompass,           ///< value: (heading + compass offset), 1 value; covariance 1x1
  kLandmarks,         ///< observations: range-bearing to landmarks; covariance 2x2 (r, beta)
  kHeartbeat,         ///< nothing; lets a receiver advance time
};

[[nodiscard]] const char* toString(EventType type);

/// One range-bearing observation: range (m) and bearing (rad, relative to the heading,
/// in [-pi, pi)) of landmark `landmark_id` (1-based, the row of the scenario's lm.txt).
struct RangeBearing {
  int landmark_id = 0;
  double range = 0.0;
  double bearing = 0.0;
};

/// A sensor event at time `time` (seconds).
struct Event {
  EventType type = EventType::kHeartbeat;
  double time = 0.0;
  Eigen::VectorXd value;
  Eigen::MatrixXd covariance;
  std::vector<RangeBearing> observations;  ///< kLandmarks only, by increasing id
};

/// Events of one step ordered by time. A new event goes before the first queued event
/// whose time is not earlier than its own, so events with equal times come out in the
/// reverse order of insertion (the coursework's OrderedEventQueue; the simulator relies
/// on it: within a step the order is odometry, compass, laser, GPS).
class OrderedEventQueue {
 public:
  void insert(Event event);
  void clear() { events_.clear(); }
  [[nodiscard]] const std::vector<Event>& events() const { return events_; }
  [[nodiscard]] bool empty() const { return events_.empty(); }

 private:
  std::vector<Event> events_;
};

}  // namespace graphslam::drivebot
