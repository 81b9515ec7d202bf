#pragma once
// The last word before a command reaches the wheels. Safety first:
//  - no link to the server for longer than link_timeout_s: stop (the path being followed may be
//    stale and nobody can see the robot);
//  - no laser scan for longer than scan_timeout_s: stop (obstacles would be invisible);
//  - an obstacle in the corridor the robot sweeps ahead within its stopping distance: no forward
//    motion (turning in place stays allowed so the controller can steer away).
#include <limits>
#include <string>

#include "drive/velocity_command.hpp"
#include "pslam/sensor/laser_scan.hpp"

namespace pslam::agent {

struct SafetyOptions {
  double robot_front_m = 0.21;       // P3-DX: front edge 210 mm ahead of the centre of rotation
  double robot_half_width_m = 0.2125;  // P3-DX width 425 mm
  double side_margin_m = 0.05;
  double stop_distance_m = 0.30;     // clearance kept between the front edge and an obstacle
  double deceleration_m_s2 = 0.3;    // ARIA's default TransDecel: braking distance v^2 / 2a
  double link_timeout_s = 1.5;
  double scan_timeout_s = 0.5;
};

enum class StopReason { kNone, kObstacle, kLinkLost, kNoScan };
const char* ToString(StopReason reason);

struct SafetyDecision {
  VelocityCommand command;
  StopReason reason = StopReason::kNone;
};

class SafetyMonitor {
 public:
  explicit SafetyMonitor(SafetyOptions options = {}) : options_(options) {}

  // Records the free distance ahead seen by 'scan' (robot frame, sensor offset applied).
  void OnScan(const LaserScan& scan, double now);
  // Filters 'wanted' at time 'now' given when the server was last heard from.
  SafetyDecision Filter(const VelocityCommand& wanted, double now, double last_server_message_time) const;

  // Distance from the robot centre to the nearest return in the forward corridor; infinity if none.
  double free_distance_ahead_m() const { return free_ahead_m_; }
  // Corridor distance from the centre below which forward motion at speed 'v' is refused.
  double StoppingDistance(double v) const;

 private:
  SafetyOptions options_;
  double free_ahead_m_ = std::numeric_limits<double>::infinity();
  double last_scan_time_ = -std::numeric_limits<double>::infinity();
};

}  // namespace pslam::agent
