#include "sources/odometry_interpolator.hpp"

#include <algorithm>

namespace pslam::agent {
namespace {
constexpr std::size_t kKeptReadings = 64;  // 6 s of SIPs: far more than any scan waits
}

void OdometryInterpolator::AddOdometry(const OdometryReading& reading) {
  if (!odometry_.empty() && reading.timestamp < odometry_.back().timestamp) return;  // out of order: ignore
  odometry_.push_back(reading);
  if (odometry_.size() > kKeptReadings) odometry_.pop_front();
}

void OdometryInterpolator::AddScan(LaserScan scan) { scans_.push_back(std::move(scan)); }

Pose2D OdometryInterpolator::PoseAt(double t) const {
  if (t <= odometry_.front().timestamp) return odometry_.front().pose;
  if (t >= odometry_.back().timestamp) return odometry_.back().pose;
  const auto after = std::lower_bound(odometry_.begin(), odometry_.end(), t,
                                      [](const OdometryReading& r, double time) { return r.timestamp < time; });
  const auto before = std::prev(after);
  const double span = after->timestamp - before->timestamp;
  const double f = span > 0 ? (t - before->timestamp) / span : 0.0;
  return Interpolate(before->pose, after->pose, f);
}

std::optional<LaserScan> OdometryInterpolator::NextReady(double now) {
  if (scans_.empty()) return std::nullopt;
  LaserScan& scan = scans_.front();
  const bool bracketed = !odometry_.empty() && odometry_.back().timestamp >= scan.timestamp;
  const bool expired = now - scan.timestamp > max_wait_s_;
  if (!bracketed && !expired) return std::nullopt;
  if (!bracketed) ++held_;
  if (!odometry_.empty()) scan.odometry = PoseAt(scan.timestamp);
  LaserScan out = std::move(scan);
  scans_.pop_front();
  return out;
}

}  // namespace pslam::agent
