#pragma once
// One planar laser scan with its geometry and the robot's raw odometry at acquisition time.
#include <cmath>
#include <string>
#include <vector>

#include "pslam/common/pose2d.hpp"

namespace pslam {

struct LaserScan {
  double timestamp = 0.0;          // seconds since the epoch (CARMEN ipc_timestamp)
  std::string timestamp_text;      // the timestamp exactly as the source wrote it, for round-trips
  std::vector<float> ranges;       // metres, counter-clockwise from angle_min
  double angle_min = 0.0;          // radians, angle of the first beam in the sensor frame
  double angle_increment = 0.0;    // radians between beams
  double max_range = 80.0;         // readings at or beyond this are "no return"
  double min_range = 0.0;          // readings at or below this are invalid
  Pose2D sensor_offset;            // sensor pose in the robot frame
  Pose2D odometry;                 // robot pose from raw odometry at `timestamp`

  double BeamAngle(std::size_t i) const { return angle_min + static_cast<double>(i) * angle_increment; }
  // A usable hit: finite, above min_range and below max_range. Everything else carries no obstacle.
  bool IsReturn(std::size_t i) const {
    const float r = ranges[i];
    return std::isfinite(r) && r > min_range && r < max_range;
  }
};

struct OdometryReading {
  double timestamp = 0.0;
  Pose2D pose;                     // raw odometry of the robot centre
  double translational_velocity = 0.0;
  double rotational_velocity = 0.0;
};

}  // namespace pslam
