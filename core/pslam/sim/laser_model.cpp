#include "pslam/sim/laser_model.hpp"

#include <algorithm>

#include "pslam/sim/ray_cast.hpp"

namespace pslam {

LaserScan SimulateScan(const World& world, const Pose2D& robot_pose, const LaserOptions& options,
                       std::mt19937_64& rng) {
  LaserScan scan;
  scan.angle_min = options.angle_min;
  scan.angle_increment = options.angle_increment;
  scan.max_range = options.max_range;
  scan.min_range = 0.0;
  scan.sensor_offset = options.sensor_offset;
  scan.ranges.resize(static_cast<std::size_t>(std::max(options.beam_count, 0)));

  const Pose2D sensor = robot_pose * options.sensor_offset;
  std::normal_distribution<double> standard_normal(0.0, 1.0);
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    const double range = CastRay(world, sensor.translation(), sensor.theta + scan.BeamAngle(i), options.max_range);
    // One draw per beam, hit or not, so that beam i always takes the i-th draw of its scan.
    const double error = std::max(options.range_noise_stddev, 0.0) * standard_normal(rng);
    const double reading = range < options.max_range ? std::clamp(range + error, 0.0, options.max_range) : options.max_range;
    scan.ranges[i] = static_cast<float>(reading);
  }
  return scan;
}

}  // namespace pslam
