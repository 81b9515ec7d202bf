#include "drive/safety.hpp"

#include <cmath>

namespace pslam::agent {

const char* ToString(StopReason reason) {
  switch (reason) {
    case StopReason::kNone: return "none";
    case StopReason::kObstacle: return "obstacle ahead";
    case StopReason::kLinkLost: return "server link lost";
    case StopReason::kNoScan: return "no laser scan";
  }
  return "?";
}

void SafetyMonitor::OnScan(const LaserScan& scan, double now) {
  const double half_width = options_.robot_half_width_m + options_.side_margin_m;
  double nearest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    if (!scan.IsReturn(i)) continue;
    const double a = scan.BeamAngle(i);
    const Eigen::Vector2d p = scan.sensor_offset * Eigen::Vector2d(scan.ranges[i] * std::cos(a), scan.ranges[i] * std::sin(a));
    if (p.x() > 0.0 && std::abs(p.y()) <= half_width) nearest = std::min(nearest, p.x());
  }
  free_ahead_m_ = nearest;
  last_scan_time_ = now;
}

double SafetyMonitor::StoppingDistance(double v) const {
  return options_.robot_front_m + options_.stop_distance_m + v * v / (2.0 * options_.deceleration_m_s2);
}

SafetyDecision SafetyMonitor::Filter(const VelocityCommand& wanted, double now, double last_server_message_time) const {
  if (now - last_server_message_time > options_.link_timeout_s) return {{}, StopReason::kLinkLost};
  if (now - last_scan_time_ > options_.scan_timeout_s) return {{}, StopReason::kNoScan};
  if (wanted.v > 0.0 && free_ahead_m_ < StoppingDistance(wanted.v)) return {{0.0, wanted.w}, StopReason::kObstacle};
  return {wanted, StopReason::kNone};
}

}  // namespace pslam::agent
