#include "pslam/experiment/log_run.hpp"

#include <chrono>
#include <cstdio>
#include <stdexcept>

#include "pslam/io/carmen_read_summary.hpp"
#include "pslam/io/carmen_reader.hpp"

namespace pslam {

void RequireMapWithinLimits(const OccupancyGrid& map, int scan_number, const std::string& stamp) {
  if (map.refused_writes() == 0) return;
  char extent[32];
  std::snprintf(extent, sizeof extent, "%g", map.limits().max_extent_meters);
  throw std::runtime_error("scan " + std::to_string(scan_number) + " (time " + stamp +
                           "): the map would reach beyond its limits (" + extent + " m from the origin, " +
                           std::to_string(map.limits().max_tile_slots) +
                           " tiles of table); the odometry is implausible");
}

LogRunResult RunLog(const std::string& log_path, PSlamOptions options, const LogProgress& progress, int max_scans) {
  options.heading_targets = true;
  CarmenReader reader(log_path);
  ScanStream scans(reader);
  PSlam slam(options);
  std::vector<std::string> stamps;
  const auto start = std::chrono::steady_clock::now();
  while (max_scans <= 0 || static_cast<int>(stamps.size()) < max_scans) {
    auto scan = scans.Next();
    if (!scan) break;
    stamps.push_back(scan->timestamp_text);
    slam.AddScan(*scan);
    RequireMapWithinLimits(slam.filter().best().map, static_cast<int>(stamps.size()), scan->timestamp_text);
    if (progress && stamps.size() % 50 == 0) progress(reader.progress(), static_cast<int>(stamps.size()));
  }
  RequireScans(reader.stats(), log_path);
  slam.FlushPredictions();
  slam.FlushLoopClosure();

  LogRunResult result;
  const std::vector<Pose2D> poses = slam.filter().Trajectory();
  result.trajectory.reserve(poses.size());
  for (std::size_t i = 0; i < poses.size() && i < stamps.size(); ++i) result.trajectory.push_back({stamps[i], 0.0, poses[i]});
  result.map = slam.filter().best().map;
  result.filter = slam.filter().stats();
  result.slam = slam.stats();
  result.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (progress) progress(1.0, static_cast<int>(stamps.size()));
  return result;
}

}  // namespace pslam
