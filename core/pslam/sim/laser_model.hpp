#pragma once
// A SICK LMS-200 as the P3-DX carries it: 181 beams over 180 degrees at 1 degree, 8 m range,
// Gaussian range noise, mounted 16 cm ahead of the robot centre.
#include <numbers>
#include <random>

#include "pslam/common/pose2d.hpp"
#include "pslam/sensor/laser_scan.hpp"
#include "pslam/sim/world.hpp"

namespace pslam {

struct LaserOptions {
  int beam_count = 181;
  double angle_min = -std::numbers::pi / 2.0;          // radians, first beam, sensor frame
  double angle_increment = std::numbers::pi / 180.0;   // radians
  double max_range = 8.0;                              // m; beams without a hit report exactly this
  double range_noise_stddev = 0.01;                    // m
  Pose2D sensor_offset{0.16, 0.0, 0.0};                // sensor pose in the robot frame
};

// The scan seen from the robot's true pose 'robot_pose': ranges and geometry filled, max_range set
// so that a beam without a hit (reported as exactly max_range) is "no return" for IsReturn.
// Noise never turns a miss into a hit: noisy hits at or beyond max_range also read max_range.
// The caller fills timestamp, timestamp_text and odometry.
LaserScan SimulateScan(const World& world, const Pose2D& robot_pose, const LaserOptions& options,
                       std::mt19937_64& rng);

}  // namespace pslam
