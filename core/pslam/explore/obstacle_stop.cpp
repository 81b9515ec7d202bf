#include "pslam/explore/obstacle_stop.hpp"

#include <algorithm>
#include <cmath>

namespace pslam {

bool ObstacleAhead(const LaserScan& scan, const ObstacleStopOptions& options) {
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    if (!scan.IsReturn(i) || scan.ranges[i] >= options.stop_distance) continue;
    const double bearing = NormalizeAngle(scan.BeamAngle(i) + scan.sensor_offset.theta);
    // Inclusive, with a hair of slack: the beam at exactly -30 degrees lands a rounding error past it.
    if (std::abs(bearing) <= options.half_angle + 1e-9) return true;
  }
  return false;
}

DriveCommand ApplyObstacleStop(const DriveCommand& command, const LaserScan& scan, const ObstacleStopOptions& options) {
  if (command.linear <= 0.0 || !ObstacleAhead(scan, options)) return command;
  return {0.0, command.angular};
}

}  // namespace pslam
