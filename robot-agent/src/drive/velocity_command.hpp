#pragma once
// A unicycle velocity command: what the controller produces, the safety layer filters and every
// scan source (robot, simulator) executes.

namespace pslam::agent {

struct VelocityCommand {
  double v = 0.0;  // m/s, forward positive
  double w = 0.0;  // rad/s, counter-clockwise positive
  bool operator==(const VelocityCommand&) const = default;
};

}  // namespace pslam::agent
