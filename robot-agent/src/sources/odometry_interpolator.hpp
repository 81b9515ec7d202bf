#pragma once
// Attaches odometry to scans stamped on arrival. Odometry comes at 10 Hz (SIP cycle) and scans at
// up to 75 Hz, each on its own clock-stamped stream, so a scan usually arrives before the odometry
// that follows it: scans wait here until odometry at or after their time exists, then get the
// linear/shortest-arc interpolation between the two readings around them. A scan that waited
// longer than max_wait_s (odometry stalled) gets the newest reading, held, and is counted.
#include <cstddef>
#include <deque>
#include <optional>

#include "pslam/sensor/laser_scan.hpp"

namespace pslam::agent {

class OdometryInterpolator {
 public:
  explicit OdometryInterpolator(double max_wait_s = 0.5) : max_wait_s_(max_wait_s) {}

  void AddOdometry(const OdometryReading& reading);
  void AddScan(LaserScan scan);
  // The oldest waiting scan, if it can be completed at time 'now' (same clock as the stamps).
  std::optional<LaserScan> NextReady(double now);

  std::size_t held_scans() const { return held_; }       // completed without a reading after them
  std::size_t waiting_scans() const { return scans_.size(); }

 private:
  Pose2D PoseAt(double t) const;

  double max_wait_s_;
  std::deque<OdometryReading> odometry_;  // time order, a couple of seconds' worth
  std::deque<LaserScan> scans_;
  std::size_t held_ = 0;
};

}  // namespace pslam::agent
