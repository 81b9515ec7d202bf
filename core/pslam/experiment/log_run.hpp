#pragma once
// P-SLAM (or the plain RBPF) over a recorded CARMEN log, start to end: what `pslam run` does,
// returned as data so that experiments can compare runs (trajectory for the relative pose error,
// final map for the KL divergence) without writing files in between.
#include <functional>
#include <string>
#include <vector>

#include "pslam/eval/trajectory_io.hpp"
#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/slam/pslam.hpp"

namespace pslam {

struct LogRunResult {
  std::vector<StampedPose> trajectory;  // one pose per scan of the log, stamped as the log wrote it
  OccupancyGrid map;                    // the best particle's map at the end
  RbpfStats filter;
  PSlamStats slam;
  double wall_time_s = 0.0;
};

// Called now and then with the fraction of the log read and the scans processed so far.
using LogProgress = std::function<void(double fraction, int scans)>;

// Maps the log with 'options' (heading_targets is forced on: a log has no planner), stopping after
// 'max_scans' scans when it is positive (quick runs). Throws std::runtime_error when the log
// cannot be read or holds no laser scans.
// Throws std::runtime_error naming scan 'scan_number' when 'map' refused cells beyond its limits
// (GridLimits): the poses are implausible and the map would be nonsense.
void RequireMapWithinLimits(const OccupancyGrid& map, int scan_number, const std::string& stamp);

LogRunResult RunLog(const std::string& log_path, PSlamOptions options, const LogProgress& progress = {},
                    int max_scans = 0);

}  // namespace pslam
