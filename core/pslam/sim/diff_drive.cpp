#include "pslam/sim/diff_drive.hpp"

#include <algorithm>
#include <cmath>

namespace pslam {
namespace {

double MoveToward(double current, double target, double max_change) {
  return current + std::clamp(target - current, -max_change, max_change);
}

}  // namespace

Twist ClampToSpeedLimits(const Twist& command, const DiffDriveOptions& o) {
  return {std::clamp(command.linear, -o.max_linear_speed, o.max_linear_speed),
          std::clamp(command.angular, -o.max_angular_speed, o.max_angular_speed)};
}

Twist StepVelocity(const Twist& current, const Twist& command, double dt, const DiffDriveOptions& o) {
  const Twist target = ClampToSpeedLimits(command, o);
  return {MoveToward(current.linear, target.linear, o.max_linear_acceleration * dt),
          MoveToward(current.angular, target.angular, o.max_angular_acceleration * dt)};
}

Pose2D IntegrateArc(const Pose2D& pose, const Twist& velocity, double dt) {
  const double v = velocity.linear, w = velocity.angular;
  const double dtheta = w * dt;
  if (std::abs(dtheta) < 1e-12) {
    return {pose.x + v * dt * std::cos(pose.theta), pose.y + v * dt * std::sin(pose.theta), pose.theta + dtheta};
  }
  const double r = v / w;  // signed turning radius
  return {pose.x + r * (std::sin(pose.theta + dtheta) - std::sin(pose.theta)),
          pose.y - r * (std::cos(pose.theta + dtheta) - std::cos(pose.theta)), pose.theta + dtheta};
}

}  // namespace pslam
