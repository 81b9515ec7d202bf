#pragma once
// Repairs ODOM poses that were integrated with the speed instead of the velocity.
//
// Some recorders add |tv| to the pose: when the robot backs up, the logged pose still moves
// forward. The Freiburg 079 log does so every time the robot backs up (its ground-truth relations
// move back), which alone put metres of error into its map. A step whose logged velocity is
// negative at either end and positive at neither, but whose pose moved forward, is re-integrated
// with its translation negated; everything after it follows the repaired pose. Logs whose poses
// agree with their velocities pass through bit for bit.
#include <cstddef>
#include <optional>

#include "pslam/common/pose2d.hpp"
#include "pslam/sensor/laser_scan.hpp"

namespace pslam {

class OdometryReversalRepair {
 public:
  // Records must come in time order: ODOM readings and the scans between them.
  void Apply(OdometryReading& odom);
  // A scan's own odometry pose (FLASER/ROBOTLASER lines) continues from the last ODOM reading.
  void Apply(LaserScan& scan) const;

  std::size_t repaired_steps() const { return repaired_steps_; }

 private:
  // The translation of `step` negated when the robot was backing up but the pose moved forward.
  static Pose2D Signed(const Pose2D& step, bool backing_up);

  std::optional<Pose2D> raw_last_;   // last ODOM pose as logged
  Pose2D repaired_last_;             // the same pose, repaired
  double velocity_last_ = 0.0;       // its translational velocity
  std::size_t repaired_steps_ = 0;
};

}  // namespace pslam
