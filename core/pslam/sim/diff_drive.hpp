#pragma once
// Differential-drive kinematics of a Pioneer 3-DX: the robot follows (v, w) commands within speed
// and acceleration limits, and moves on exact circular arcs between physics ticks.
#include <numbers>

#include "pslam/common/pose2d.hpp"

namespace pslam {

struct Twist {
  double linear = 0.0;   // m/s, forward positive
  double angular = 0.0;  // rad/s, counter-clockwise positive
};

struct DiffDriveOptions {
  double max_linear_speed = 0.2;                                  // m/s: the paper's top speed (Sec. V-A)
  double max_angular_speed = 100.0 * std::numbers::pi / 180.0;    // rad/s
  // ARIA's default P3-DX accelerations (TransAccel 300 mm/s^2, RotAccel 100 deg/s^2).
  double max_linear_acceleration = 0.3;                           // m/s^2
  double max_angular_acceleration = 100.0 * std::numbers::pi / 180.0;  // rad/s^2
  double robot_radius = 0.25;                                     // m: collision disc
};

// 'command' clamped to the speed limits.
Twist ClampToSpeedLimits(const Twist& command, const DiffDriveOptions& options);

// The velocity after 'dt' seconds of moving from 'current' toward 'command' at no more than the
// acceleration limits (the command is clamped to the speed limits first).
Twist StepVelocity(const Twist& current, const Twist& command, double dt, const DiffDriveOptions& options);

// The pose after driving at constant 'velocity' for 'dt' seconds: the exact circular arc (a
// straight line when angular is zero), not an Euler step, so long ticks stay on the true path.
Pose2D IntegrateArc(const Pose2D& pose, const Twist& velocity, double dt);

}  // namespace pslam
