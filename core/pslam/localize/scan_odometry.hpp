#pragma once
// Wheel odometry corrected by scan matching against a local map of the last scans, for Monte
// Carlo localization where the fixed map explains little of what the robot sees (a place the map
// saw only from afar, or not at all): there the likelihood field carries little information, the
// particles follow odometry, and raw odometry is what limits the estimate. Matching each scan
// against the scans just before it is what the mapping filter's tracking does on its own map.
//
// Two local maps are kept, as Cartographer keeps two active submaps: each scan is matched against
// the older, fuller one and inserted into both; once the newer holds scans_per_map scans the older
// is dropped and a new one started. Memory stays bounded whatever the run's length.
#include <vector>

#include "pslam/common/pose2d.hpp"
#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/grid/scan_inserter.hpp"
#include "pslam/matching/scan_matcher.hpp"
#include "pslam/sensor/laser_scan.hpp"
#include "pslam/sensor/scan_points.hpp"

namespace pslam {

struct ScanOdometryOptions {
  bool enabled = true;
  int scans_per_map = 30;     // scans a local map takes before the next one starts
  double resolution = 0.05;   // metres per cell of the local maps
  ScanMatchOptions match{.coarsest_level = 2, .degenerate_ratio = 0.15};
  double min_constrained_ratio = 0.3;  // TranslationConstraintRatio a match needs to be used
  ScanPointsOptions points{.max_usable_range = 20.0, .no_return_free_range = 0.0, .min_point_spacing = 0.03};
};

class ScanOdometry {
 public:
  explicit ScanOdometry(const ScanOdometryOptions& options);

  // The scan's pose in the odometry frame, corrected by the match: the first scan keeps its raw
  // odometry, each later one moves from the previous corrected pose by the matched motion (the
  // raw odometry's motion where the match fails).
  Pose2D Correct(const LaserScan& scan);

 private:
  ScanOdometryOptions options_;
  ScanInserter inserter_;
  std::vector<OccupancyGrid> maps_;  // oldest first, at most two
  int scans_in_newest_ = 0;
  bool started_ = false;
  Pose2D last_raw_, last_corrected_;
};

}  // namespace pslam
