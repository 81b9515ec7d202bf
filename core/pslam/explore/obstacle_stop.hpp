#pragma once
// A last line of defence between the planner and the wheels: whatever the map says, do not drive
// forward into something the laser sees right now (a map built from an estimated pose can be off,
// and a path plans only around what was mapped).
#include <numbers>

#include "pslam/explore/path_follower.hpp"
#include "pslam/sensor/laser_scan.hpp"

namespace pslam {

struct ObstacleStopOptions {
  double stop_distance = 0.35;                           // m, as the sensor measures it
  double half_angle = 30.0 * std::numbers::pi / 180.0;   // rad either side of the robot's heading
};

// True when 'scan' has a return closer than stop_distance at a bearing (in the robot frame:
// beam angle plus the sensor's mounting angle) within half_angle of straight ahead.
bool ObstacleAhead(const LaserScan& scan, const ObstacleStopOptions& options = {});

// 'command' with forward motion removed when ObstacleAhead: turning and reversing stay allowed,
// so the robot can still turn away.
DriveCommand ApplyObstacleStop(const DriveCommand& command, const LaserScan& scan,
                               const ObstacleStopOptions& options = {});

}  // namespace pslam
