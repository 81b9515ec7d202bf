#include "pslam/localize/scan_odometry.hpp"

namespace pslam {

ScanOdometry::ScanOdometry(const ScanOdometryOptions& options) : options_(options) {}

Pose2D ScanOdometry::Correct(const LaserScan& scan) {
  const ScanPoints points = ToScanPoints(scan, options_.points);
  Pose2D pose = scan.odometry;
  if (started_) {
    pose = last_corrected_ * Between(last_raw_, scan.odometry);
    if (!points.hits.empty()) {
      const ScanMatchResult match = MatchScan(maps_.front(), points.hits, pose, options_.match);
      // Where the scan pins the position down in one direction only (a corridor), the match can
      // slide along it: the wheels are trusted there instead.
      if (match.converged && TranslationConstraintRatio(match.hessian) >= options_.min_constrained_ratio) pose = match.pose;
    }
  }
  started_ = true;
  last_raw_ = scan.odometry;
  last_corrected_ = pose;

  if (maps_.empty() || scans_in_newest_ >= options_.scans_per_map) {
    if (maps_.size() == 2) maps_.erase(maps_.begin());
    maps_.emplace_back(options_.resolution);
    scans_in_newest_ = 0;
  }
  for (OccupancyGrid& map : maps_) inserter_.Insert(points, pose, map);
  ++scans_in_newest_;
  return pose;
}

}  // namespace pslam
