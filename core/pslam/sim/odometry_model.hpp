#pragma once
// Wheel odometry that drifts like a real robot's. Two error sources, both seeded:
//  - systematic calibration errors (wheel radius, wheelbase), drawn once: every metre driven and
//    every radian turned is mis-scaled by the same factor, so the error grows linearly with
//    distance and bends straight runs into arcs, as uncalibrated encoders do;
//  - random per-tick errors (slip, uneven floor) whose variance is proportional to the distance
//    driven and the angle turned, so their spread grows with the square root of the distance.
// A robot that does not move accumulates no error.
#include <cstdint>
#include <random>

#include "pslam/common/pose2d.hpp"

namespace pslam {

struct OdometryNoiseOptions {
  double translation_scale_error_stddev = 0.01;   // wheel-radius error: 1 % of distance driven
  double rotation_scale_error_stddev = 0.02;      // wheelbase error: 2 % of angle turned
  double translation_stddev_per_sqrt_meter = 0.01;  // m of random error after driving 1 m
  double rotation_stddev_per_sqrt_meter = 0.01;     // rad of heading error after driving 1 m
  double rotation_stddev_per_sqrt_radian = 0.02;    // rad of heading error after turning 1 rad
};

class DriftingOdometry {
 public:
  // Odometry starting at 'start'; 'seed' fixes both the calibration errors and the random walk.
  DriftingOdometry(const Pose2D& start, const OdometryNoiseOptions& options, std::uint64_t seed);

  // Accounts for one true motion 'increment' of the robot, expressed in the robot's frame before
  // the motion (Between(before, after)), and returns the new odometry pose.
  const Pose2D& Advance(const Pose2D& increment);

  const Pose2D& pose() const { return pose_; }
  // Visible for testing: the calibration factors drawn for this seed.
  double translation_scale() const { return translation_scale_; }
  double rotation_scale() const { return rotation_scale_; }

 private:
  OdometryNoiseOptions options_;
  std::mt19937_64 rng_;
  double translation_scale_;
  double rotation_scale_;
  Pose2D pose_;
};

}  // namespace pslam
